"""The HTML reports of imuconv check, montecarlo and nees (--report OUT.html), end to end.

Always: each command writes its report from in-repository data; the document is well-formed XML
(xml.etree), holds the expected SVG figures (heatmaps with 5 (3, 2) block labels per axis and one
cell per entry, charts), names its inputs as given (a directory name full of markup characters,
which must come back as the same text after parsing, i.e. escaped), loads nothing (no src/href, no
script, a Content-Security-Policy refusing every fetch), and the command's own stdout is byte for
byte the same with and without --report. A report path that is a directory, in a missing
directory, or an input file is refused with exit 2, leaving no file and no temporary.

With --chromium PATH: each report is also rendered by headless Chromium, which must print no
console message at all (the report has no script, so any message is an error: a CSP violation,
a failed load), request nothing over the network from the page (its net log), have every SVG in
its DOM, and paint a PNG that is not blank. A control page with an external image and a script
error must trip both detectors, so the checks are known to see what they look for.

Every heatmap a judgment is read from carries its anchored colour scale (data-scale-min,
data-scale-max, data-tolerance; the tolerance inside the range and marked on the legend), and the
check and montecarlo pages open with the verdict badge (data-verdict, agreeing with the exit code)
before any other content. The nees page states the two factors and the offset flags.

With --screenshots DIR: also writes each report's rendering, cropped to its top, as
DIR/report-{check,montecarlo,nees}.png (docs/img/).

With --readme-image OUT.png: renders the first measurement's heatmaps of the check report alone
(docs/img/, the README's picture) and exits.
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zlib

SVG = "{http://www.w3.org/2000/svg}"
XHTML = "{http://www.w3.org/1999/xhtml}"

failures = []


def fail(msg):
    print("FAIL " + msg)
    failures.append(msg)


def run(argv, env):
    return subprocess.run(argv, capture_output=True, env=env, timeout=300)


def commands(binary, src, work):
    """The three commands on in-repository data: (name, argv without --report, inputs, exit codes).
    montecarlo's verdict on 200 trials is either (a 95 % bound is missed by chance one time in
    twenty, and its generator is free to change): the report is written for both."""
    # A directory name with every character markup gives meaning to.
    hostile = os.path.join(work, "in <b>&amp; \"q\" 'a'")
    os.makedirs(hostile, exist_ok=True)
    meas = os.path.join(hostile, "meas.json")
    shutil.copy(os.path.join(src, "examples/data/gtsam_smooth0_manifold.measurements.json"), meas)
    case = os.path.join(src, "tests/data/reference/cases/smooth-0.json")
    noise = os.path.join(work, "noise.json")
    # The EuRoC datasheet densities (examples/euroc_v1_01_keyframes.json's noise).
    with open(noise, "w") as f:
        f.write('{"gyro_noise_density": 1.6968e-04, "accel_noise_density": 2.0e-3, '
                '"gyro_random_walk": 1.9393e-05, "accel_random_walk": 3.0e-3}')
    imu = os.path.join(src, "examples/data/V1_01_easy_imu0_slice.csv")
    gt = os.path.join(src, "examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv")
    return [
        ("check", [binary, "check", meas, "--case", case], [meas, case], {0}),
        ("montecarlo", [binary, "montecarlo", "--case", case, "--method", "euler", "--trials", "200", "--seed", "1",
                        "--duration", "1", "--threads", "2"], [case], {0, 1}),
        ("nees", [binary, "nees", "--imu", imu, "--ground-truth", gt, "--noise", noise, "--windows", "0.5,1.0",
                  "--method", "rk4"], [imu, gt, noise], {0}),
    ]


def classes(elem, tag, cls):
    return [e for e in elem.iter(tag) if e.get("class") == cls]


def check_heatmap(name, svg, rows, cols):
    cells = classes(svg, SVG + "rect", "cell")
    if len(cells) != rows * cols:
        fail(f"{name}: {len(cells)} cells, expected {rows * cols}")
    for cls, n in (("row-block", rows // 3), ("col-block", cols // 3)):
        got = classes(svg, SVG + "text", cls)
        if len(got) != n:
            fail(f"{name}: {len(got)} {cls} labels, expected {n}")
    ticks = classes(svg, SVG + "text", "legend-tick")
    if len(ticks) < 2 or not all(re.fullmatch(r"[\u2264\u2265]?(1e-?\d+|-?\d+(\.\d+)?)", t.text or "") for t in ticks):
        fail(f"{name}: legend ticks {[t.text for t in ticks]}")
    # The anchored scale: its range and tolerance as attributes, the tolerance inside the range
    # and marked across the legend's bar (twice, +-, on a signed map).
    try:
        lo, hi, tol = (float(svg.get(a)) for a in ("data-scale-min", "data-scale-max", "data-tolerance"))
    except (TypeError, ValueError):
        fail(f"{name}: no anchored scale attributes {dict(svg.attrib)}")
        return
    kind = svg.get("data-scale-kind")
    if not (lo < tol < hi) or kind not in ("magnitude", "signed") or (kind == "signed" and lo != -hi):
        fail(f"{name}: scale {kind} [{lo}, {hi}] with tolerance {tol}")
    marks = [l for l in svg.iter(SVG + "line") if l.get("class") == "legend-tolerance"]
    if len(marks) != (2 if kind == "signed" else 1):
        fail(f"{name}: {len(marks)} tolerance marks on the legend")
    # No cell is painted white, the page's colour, where it could pass for a missing entry.
    if any(c.get("fill") == "#ffffff" for c in cells):
        fail(f"{name}: a white cell")
    # Every cell has its hover title and a colour.
    for c in cells:
        if c.find(SVG + "title") is None or not re.fullmatch(r"#[0-9a-f]{6}", c.get("fill", "")):
            fail(f"{name}: a cell without a title or colour")
            break


def check_document(name, path, inputs, verdict=None):
    """Returns the number of <svg> elements, for the browser's DOM check."""
    text = open(path, encoding="utf-8").read()
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        fail(f"{name}: not well-formed XML: {e}")
        return 0
    # Nothing that loads: no script, no src/href attribute, no url() in a style.
    for e in root.iter():
        if e.tag in (XHTML + "script", SVG + "script", XHTML + "link", XHTML + "img", XHTML + "iframe"):
            fail(f"{name}: has a <{e.tag}> element")
        for a in e.attrib:
            if a.split("}")[-1] in ("src", "href") or a.startswith("on"):
                fail(f"{name}: <{e.tag}> has the attribute {a}")
    if "url(" in text or "@import" in text:
        fail(f"{name}: a style refers to a URL")
    csp = [m for m in root.iter(XHTML + "meta") if m.get("http-equiv") == "Content-Security-Policy"]
    if not csp or "default-src 'none'" not in csp[0].get("content", ""):
        fail(f"{name}: no Content-Security-Policy refusing every load")
    # The inputs as given, text for text (escaped in the file, whole again once parsed).
    cells = {"".join(td.itertext()) for td in root.iter(XHTML + "td")}
    for i in inputs:
        if i not in cells:
            fail(f"{name}: the input {i!r} is not named as given")
    # The verdict badge: the first thing in the body after the title (check, montecarlo).
    body = root.find(XHTML + "body")
    badges = [d for d in root.iter(XHTML + "div") if d.get("class") == "verdict"]
    if name in ("check", "montecarlo"):
        first = [e for e in body if e.tag != XHTML + "h1"][:1] if body is not None else []
        if len(badges) != 1 or not first or first[0] is not badges[0]:
            fail(f"{name}: the verdict badge is not the first element under the title ({len(badges)} badges)")
        elif badges[0].get("data-verdict") not in ("consistent", "inconsistent") or \
                not "".join(badges[0].itertext()).strip():
            fail(f"{name}: badge {badges[0].attrib} {''.join(badges[0].itertext())!r}")
        elif verdict is not None and badges[0].get("data-verdict") != verdict:
            fail(f"{name}: badge says {badges[0].get('data-verdict')}, the exit code {verdict}")
    svgs = [s for s in root.iter(SVG + "svg") if s.get("class") in ("heatmap", "chart")]
    heatmaps = [s for s in svgs if s.get("class") == "heatmap"]
    charts = [s for s in svgs if s.get("class") == "chart"]
    if name == "check":
        # One measurement: J_bias 9x6 (3 by 2 blocks) and the covariance 15x15 (5 by 5).
        if len(heatmaps) != 2:
            fail(f"check: {len(heatmaps)} heatmaps, expected 2")
        else:
            check_heatmap("check J_bias", heatmaps[0], 9, 6)
            check_heatmap("check cov", heatmaps[1], 15, 15)
    elif name == "montecarlo":
        if len(heatmaps) != 2:
            fail(f"montecarlo: {len(heatmaps)} heatmaps, expected 2")
        for h in heatmaps:
            check_heatmap("montecarlo", h, 15, 15)
        # The per-trial NEES histogram: its bars and chi-square(15)'s mean and bounds.
        bars = [r for c in charts for g in c.iter(SVG + "g") if g.get("class") == "bars" for r in g]
        refs = [l for c in charts for l in c.iter(SVG + "line") if l.get("class") == "reference"]
        if len(charts) != 1 or not bars or len(refs) != 3:
            fail(f"montecarlo: {len(charts)} charts, {len(bars)} bars, {len(refs)} reference lines; expected the "
                 f"NEES histogram with 3")
    elif name == "nees":
        # Two window lengths: NEES over time and its histogram, then 9 error components, each.
        if len(charts) != 2 * 11:
            fail(f"nees: {len(charts)} charts, expected 22")
        bands = [p for c in charts for p in c.iter(SVG + "polygon") if p.get("class") == "band"]
        if len(bands) != 18:
            fail(f"nees: {len(bands)} +-3 sigma bands, expected 18")
        refs = [l for c in charts for l in c.iter(SVG + "line") if l.get("class") == "reference"]
        if len(refs) != 2 * (3 + 2):
            fail(f"nees: {len(refs)} chi-square reference lines, expected 10")
        # The two factors and the offsets, per window length, beside the plots.
        paragraphs = ["".join(p.itertext()) for p in root.iter(XHTML + "p")]
        factor_lines = [p for p in paragraphs if re.match(r"Factors: k \(all\) [\d.]+, k_gyro [\d.]+, k_accel [\d.]+\. "
                                                          r"Offsets: ", p)]
        if len(factor_lines) != 2:
            fail(f"nees: {len(factor_lines)} factor lines, expected one per window length")
        headers = ["".join(th.itertext()) for th in root.iter(XHTML + "th")]
        if not {"k_gyro", "k_accel", "offsets"} <= set(headers):
            fail(f"nees: the summary table lacks k_gyro, k_accel or offsets: {headers}")
    return len(list(root.iter(SVG + "svg")))  # nested ones (a chart's plot area) included


def check_refusals(binary, argv, inputs, work, env):
    for label, target in (("a directory", work), ("a missing directory", os.path.join(work, "no/such/dir/r.html")),
                          ("an input", inputs[0])):
        before = open(target, "rb").read() if os.path.isfile(target) else None
        listing = sorted(os.listdir(os.path.dirname(target) if before is not None else work))
        p = run(argv + ["--report", target], env)
        err = p.stderr.decode(errors="replace")
        if p.returncode != 2 or "--report" not in err:
            fail(f"{argv[1]} --report {label}: exit {p.returncode}, stderr {err[:300]!r}")
        if before is not None and open(target, "rb").read() != before:
            fail(f"{argv[1]} --report {label}: the input was changed")
        after = sorted(os.listdir(os.path.dirname(target) if before is not None else work))
        if after != listing:
            fail(f"{argv[1]} --report {label}: left {set(after) - set(listing)}")


# ---- PNG, for the rendered pages: decoded with zlib and NumPy ----

def _average_or_paeth(f, line, prev, bpp):
    """One row of PNG filter 3 (Average) or 4 (Paeth), byte by byte (each needs the one
    reconstructed bpp before it, so this part cannot be vectorized)."""
    import numpy as np
    n = len(line)
    cur = line[:bpp]
    if f == 3:
        cur = [(line[i] + (prev[i] >> 1)) & 0xFF for i in range(bpp)]
        for i in range(bpp, n):
            cur.append((line[i] + ((cur[i - bpp] + prev[i]) >> 1)) & 0xFF)
    else:
        cur = [(line[i] + prev[i]) & 0xFF for i in range(bpp)]  # a = c = 0: the predictor is b
        for i in range(bpp, n):
            a, b, c = cur[i - bpp], prev[i], prev[i - bpp]
            pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
            cur.append((line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF)
    return np.array(cur, dtype=np.uint8)


def png_pixels(path):
    import numpy as np
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or color not in (2, 6) or interlace:
                raise ValueError(f"unexpected PNG kind: depth {depth}, colour {color}, interlace {interlace}")
        elif kind == b"IDAT":
            idat += body
    bpp = 3 if color == 2 else 4
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, w * bpp + 1)
    out = np.zeros((h, w * bpp), dtype=np.uint8)
    prev = np.zeros(w * bpp, dtype=np.uint8)
    for r in range(h):
        f, line = raw[r, 0], raw[r, 1:]
        if f == 0:
            cur = line.copy()
        elif f == 1:  # Sub: a running sum per channel, modulo 256
            cur = np.cumsum(line.reshape(w, bpp), axis=0, dtype=np.uint8).reshape(-1)
        elif f == 2:  # Up
            cur = line + prev
        else:  # Average, Paeth: each byte needs the one reconstructed before it
            cur = _average_or_paeth(f, line.tolist(), prev.tolist(), bpp)
        out[r] = cur
        prev = out[r]
    return out.reshape(h, w, bpp)[:, :, :3]


CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--disable-default-apps", "--hide-scrollbars", "--enable-logging=stderr", "--v=0"]


def render(chromium, html, png, size, work, scale=None):
    """Renders html to png; returns (DOM text, console lines, page-initiated URLs). scale: a device
    scale factor (the screenshots for docs/img are drawn at 0.75 to stay small)."""
    import json
    profile = tempfile.mkdtemp(dir=work, prefix="profile")
    netlog = os.path.join(work, "netlog.json")
    p = subprocess.run([chromium] + CHROMIUM_FLAGS + ["--user-data-dir=" + profile, "--log-net-log=" + netlog,
                                                      "--window-size=" + size, "--screenshot=" + png, "--dump-dom"]
                       + (["--force-device-scale-factor=" + str(scale)] if scale else []) + [
                                                      "file://" + os.path.abspath(html)],
                       capture_output=True, timeout=60, env=dict(os.environ, HOME=work))
    if p.returncode != 0:
        raise RuntimeError(f"chromium exited {p.returncode}: {p.stderr.decode(errors='replace')[-800:]}")
    console = [l for l in p.stderr.decode(errors="replace").splitlines() if ":CONSOLE" in l]
    # The page's own requests carry its file:// network isolation key; the browser's background
    # traffic (update checks, which the flags above mostly but not always silence) carries none.
    page_urls = []
    log = json.load(open(netlog))
    kinds = {v: k for k, v in log["constants"]["logEventTypes"].items()}
    for e in log["events"]:
        params = e.get("params", {})
        if kinds.get(e["type"]) == "URL_REQUEST_START_JOB" and "file://" in params.get("network_isolation_key", ""):
            page_urls.append(params.get("url"))
    shutil.rmtree(profile, ignore_errors=True)
    return p.stdout.decode(errors="replace"), console, page_urls


def chromium_checks(chromium, reports, work, screenshots=None):
    # The control: an external image without a policy, and a script error.
    control = os.path.join(work, "control.html")
    with open(control, "w") as f:
        f.write('<!DOCTYPE html><html><body><p>control</p><img src="http://example.invalid/x.png"/>'
                '<script>undefined_function();</script></body></html>')
    _, console, urls = render(chromium, control, os.path.join(work, "control.png"), "400,300", work)
    if not console or not urls:
        fail(f"chromium control: the detectors did not fire (console {console}, page URLs {urls})")
    for name, html, n_svg, fills in reports:
        png = os.path.join(work, name + ".png")
        dom, console, urls = render(chromium, html, png, "1280,1400", work)
        if console:
            fail(f"chromium {name}: console messages: {console[:3]}")
        if urls:
            fail(f"chromium {name}: the page requested {urls[:3]}")
        if dom.count("<svg") != n_svg:
            fail(f"chromium {name}: {dom.count('<svg')} <svg> in the DOM, expected {n_svg}")
        px = png_pixels(png)
        non_white = (px.min(axis=2) < 250).mean()
        painted = {tuple(c) for c in px.reshape(-1, 3).tolist()}
        # A page of tables and figures: well over 2 % of its pixels painted, many colours (the
        # heatmaps' and charts'); a blank or failed page is one colour.
        if non_white < 0.02 or len(painted) < 16:
            fail(f"chromium {name}: the PNG looks blank ({100 * non_white:.1f} % painted, {len(painted)} colours)")
        # Every heatmap cell is a solid square of 22 px: each colour the document gives a cell is
        # painted exactly, somewhere inside its square (the window is tall enough for them all).
        missing = [f for f in fills if tuple(int(f[i:i + 2], 16) for i in (1, 3, 5)) not in painted]
        if missing:
            fail(f"chromium {name}: {len(missing)} of {len(fills)} cell colours not painted, e.g. {missing[:3]}")
        print(f"ok   chromium {name}: {100 * non_white:.1f} % painted, {len(painted)} colours, "
              f"{len(fills) - len(missing)} of {len(fills)} cell colours, {n_svg} svg in the DOM")
        # The badge is painted: its background colour (html_document.cpp's style) is in the PNG.
        if name in ("check", "montecarlo") and not painted & {(0x1b, 0x7a, 0x35), (0xa5, 0x0f, 0x15)}:
            fail(f"chromium {name}: the verdict badge's colour is not painted")
        if screenshots:
            shot = os.path.join(screenshots, f"report-{name}.png")
            size = {"check": "1100,1250", "montecarlo": "1000,2450", "nees": "1100,1600"}[name]
            render(chromium, html, shot, size, work, 0.75)
            print(f"wrote {shot} ({os.path.getsize(shot)} bytes)")


def readme_image(chromium, check_html, out, work):
    root = ET.parse(check_html).getroot()
    figs = root.find(f".//{XHTML}div[@class='figures']")
    for e in root.iter():  # serialize without namespace prefixes
        e.tag = e.tag.split("}")[-1]
    page = os.path.join(work, "readme.html")
    with open(page, "w", encoding="utf-8") as f:
        f.write('<!DOCTYPE html><html><head><meta charset="utf-8"/><style>body{font-family:sans-serif;margin:8px}'
                '.figures{display:flex;gap:1.2em;align-items:flex-start}figure{margin:0;display:table}'
                'figcaption{display:table-caption;caption-side:bottom;font-size:0.85em;color:#444}'
                '</style></head><body>')
        f.write(ET.tostring(figs, encoding="unicode").replace("<svg ", '<svg xmlns="http://www.w3.org/2000/svg" ', ))
        f.write("</body></html>")
    render(chromium, page, out, "960,470", work)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    ap.add_argument("--chromium")
    ap.add_argument("--readme-image")
    ap.add_argument("--screenshots")
    a = ap.parse_args()
    env = dict(os.environ)
    env.pop("IMUCONV_PLUGIN_PATH", None)
    work = tempfile.mkdtemp(prefix="imuconv_report_")
    try:
        reports = []
        for name, argv, inputs, code in commands(a.binary, a.source_dir, work):
            html = os.path.join(work, name + ".html")
            plain = run(argv, env)
            with_report = run(argv + ["--report", html], env)
            if plain.returncode not in code or with_report.returncode != plain.returncode:
                fail(f"{name}: exit {plain.returncode} / {with_report.returncode} with --report, expected {code}: "
                     f"{with_report.stderr.decode(errors='replace')[:400]}")
                continue
            if plain.stdout != with_report.stdout:
                fail(f"{name}: stdout differs with --report")
            if a.readme_image and name == "check":
                readme_image(a.chromium, html, a.readme_image, work)
                print("wrote " + a.readme_image)
                return 0
            verdict = {0: "consistent", 1: "inconsistent"}.get(plain.returncode) if name != "nees" else None
            n_svg = check_document(name, html, inputs, verdict)
            print(f"ok   {name}: {os.path.getsize(html)} bytes, {n_svg} figures")
            fills = set(re.findall(r'fill="(#[0-9a-f]{6})" class="cell"', open(html, encoding="utf-8").read()))
            reports.append((name, html, n_svg, fills))
            check_refusals(a.binary, argv, inputs, work, env)
        if a.chromium:
            chromium_checks(a.chromium, reports, work, a.screenshots)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
