// The report library's writers (apps/report/): text escaping, the log colour scale, the anchored
// colour scale, the heatmap and chart SVG, the HTML document and its verdict badge. The documents'
// well-formedness as XML and their rendering in a browser are checked on the commands' real reports
// by tests/report/report_documents.py.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "imuconv/report/anchored_scale.h"
#include "imuconv/report/chart.h"
#include "imuconv/report/color_scale.h"
#include "imuconv/report/heatmap.h"
#include "imuconv/report/html_document.h"
#include "imuconv/report/markup.h"
#include "text_contains.h"

namespace {
using namespace imuconv::report;
using imuconv::test::Count;
using imuconv::test::Has;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

int Channel(const std::string& hex, int k) {
  return std::stoi(hex.substr(1 + 2 * k, 2), nullptr, 16);
}

// ---- markup ----

TEST(Markup, EscapesTheFiveMarkupCharacters) {
  EXPECT_EQ(EscapeText("<b>&\"x'</b>"), "&lt;b&gt;&amp;&quot;x&#39;&lt;/b&gt;");
  EXPECT_EQ(EscapeText("&amp;"), "&amp;amp;");  // already-escaped text is text: escaped again
  EXPECT_EQ(EscapeText("plain text, 1.5 s"), "plain text, 1.5 s");
}

TEST(Markup, KeepsValidUtf8AndReplacesWhatXmlCannotHold) {
  EXPECT_EQ(EscapeText("\xce\xb8 \xc2\xb1 \xe2\x89\xa4"),
            "\xce\xb8 \xc2\xb1 \xe2\x89\xa4");  // θ ± ≤
  const std::string r = "\xEF\xBF\xBD";         // U+FFFD
  EXPECT_EQ(EscapeText(std::string("a\x01z", 3)), "a" + r + "z");
  EXPECT_EQ(EscapeText(std::string("a\0z", 3)), "a" + r + "z");
  EXPECT_EQ(EscapeText("tab\tand\nnewline"), "tab\tand\nnewline");
  EXPECT_EQ(EscapeText("\xff"), r);                  // never a UTF-8 byte
  EXPECT_EQ(EscapeText("\xc3"), r);                  // a truncated sequence
  EXPECT_EQ(EscapeText("\xc0\xaf"), r + r);          // an overlong '/'
  EXPECT_EQ(EscapeText("\xed\xa0\x80"), r + r + r);  // a UTF-16 surrogate
  EXPECT_EQ(EscapeText("\xef\xbf\xbf"), r + r + r);  // U+FFFF, not an XML character
}

TEST(Markup, CoordinatesAreShortFixedPoint) {
  EXPECT_EQ(Coordinate(12.5), "12.5");
  EXPECT_EQ(Coordinate(3.0), "3");
  EXPECT_EQ(Coordinate(100.0), "100");
  EXPECT_EQ(Coordinate(-0.001), "0");
  EXPECT_EQ(Coordinate(1.006), "1.01");
  EXPECT_EQ(Coordinate(kNaN), "0");
  EXPECT_EQ(Readable(kNaN), "NaN");
  EXPECT_EQ(Readable(-kInf), "-inf");
  EXPECT_EQ(Readable(1.23456e-7, 3), "1.23e-07");
}

// ---- the colour scale ----

TEST(ColorScale, ViridisAtItsSamplesAndBetween) {
  EXPECT_EQ(Viridis(0.0).Hex(), "#440154");
  EXPECT_EQ(Viridis(1.0).Hex(), "#fde725");
  EXPECT_EQ(Viridis(4.0 / 9.0).Hex(), "#26828e");
  EXPECT_EQ(Viridis(-1.0).Hex(), "#440154");  // clamped
  EXPECT_EQ(Viridis(kNaN).Hex(), "#440154");
  // matplotlib's viridis at 0.5 is (0.127568, 0.566949, 0.550556) = #21918c. Straight lines
  // between samples 1/9 apart stay within 3 of 255 of the curved map there (measured 2).
  const std::string mid = Viridis(0.5).Hex();
  const int ref[3] = {0x21, 0x91, 0x8c};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(Channel(mid, k), ref[k], 3) << mid;
}

TEST(ColorScale, DecadesMapLinearlyAndClampAtTheEnds) {
  const LogColorScale s(-12, 0);
  EXPECT_DOUBLE_EQ(s.Position(1e-12), 0.0);
  EXPECT_DOUBLE_EQ(s.Position(1.0), 1.0);
  EXPECT_NEAR(s.Position(1e-6), 0.5, 1e-15);  // log10 of a power of ten: exact to round-off
  EXPECT_NEAR(s.Position(1e-3), 0.75, 1e-15);
  EXPECT_EQ(s.Color(1e-6), Viridis(0.5));
  EXPECT_EQ(s.Color(1e-20), Viridis(0.0));
  EXPECT_EQ(s.Color(1e5), Viridis(1.0));
  EXPECT_TRUE(s.Clamped(1e-20));
  EXPECT_TRUE(s.Clamped(1e5));
  EXPECT_FALSE(s.Clamped(1e-12));
  EXPECT_FALSE(s.Clamped(0.5));
  EXPECT_THROW(LogColorScale(0, 0), std::invalid_argument);
}

TEST(ColorScale, SpecialEntriesHaveColoursNoValueHas) {
  const LogColorScale s(-3, 0);
  EXPECT_EQ(s.Color(0.0), SpecialColor(EntryKind::zero));
  EXPECT_EQ(s.Color(-0.0), SpecialColor(EntryKind::zero));
  EXPECT_EQ(s.Color(kNaN), SpecialColor(EntryKind::not_a_number));
  EXPECT_EQ(s.Color(kInf), SpecialColor(EntryKind::infinite));
  EXPECT_EQ(s.Color(-kInf), SpecialColor(EntryKind::infinite));
  EXPECT_EQ(s.Color(-1e-3), SpecialColor(EntryKind::negative));
  for (EntryKind k :
       {EntryKind::zero, EntryKind::not_a_number, EntryKind::infinite, EntryKind::negative})
    for (int i = 0; i <= 1024; ++i)
      EXPECT_FALSE(Viridis(i / 1024.0) == SpecialColor(k)) << KindName(k) << " " << i;
}

TEST(ColorScale, FitSpansTheValuesDecades) {
  const LogColorScale a = LogColorScale::Fit({3e-13, 2e-5, 0.0, kNaN, -1.0, kInf});
  EXPECT_EQ(a.lo_decade(), -13);
  EXPECT_EQ(a.hi_decade(), -4);
  const LogColorScale one = LogColorScale::Fit({2.0, 3.0});
  EXPECT_EQ(one.lo_decade(), 0);
  EXPECT_EQ(one.hi_decade(), 1);
  const LogColorScale none = LogColorScale::Fit({0.0, kNaN});
  EXPECT_EQ(none.lo_decade(), -1);
  EXPECT_EQ(none.hi_decade(), 0);
  const LogColorScale wide =
      LogColorScale::Fit({1e-30, 0.5}, 16);  // the large ones keep their colours
  EXPECT_EQ(wide.lo_decade(), -16);
  EXPECT_EQ(wide.hi_decade(), 0);
}

// ---- the heatmap ----

HeatmapSpec Spec15() {
  HeatmapSpec h;
  h.values = Eigen::MatrixXd::Constant(15, 15, 1e-6);
  h.row_blocks = h.col_blocks = {"theta", "p", "v", "bg", "ba"};
  h.scale = LogColorScale(-12, 0);
  return h;
}

TEST(Heatmap, OneCellPerEntryAndTheBlockLabelsOnBothAxes) {
  HeatmapSpec h = Spec15();
  h.values(0, 0) = 1e-12;
  const std::string svg = HeatmapSvg(h);
  EXPECT_EQ(Count(svg, "class=\"cell\""), 225u);
  EXPECT_EQ(Count(svg, "class=\"row-block\""), 5u);
  EXPECT_EQ(Count(svg, "class=\"col-block\""), 5u);
  EXPECT_EQ(Count(svg, "class=\"row-entry\""), 15u);
  EXPECT_EQ(Count(svg, "class=\"col-entry\""), 15u);
  EXPECT_EQ(Count(svg, "<svg"), 1u);
  EXPECT_EQ(Count(svg, "</svg>"), 1u);
  EXPECT_TRUE(Has(svg, ">theta</text>") && Has(svg, ">ba</text>"));
  // The colours: 1e-6 is the scale's middle, 1e-12 its bottom; the hover titles name the entry.
  EXPECT_EQ(Count(svg, "fill=\"" + Viridis(0.5).Hex() + "\" class=\"cell\""), 224u);
  EXPECT_TRUE(
      Has(svg, "fill=\"#440154\" class=\"cell\"><title>theta.x, theta.x: d = 1e-12</title>"));
  // Legend: 12 decades, a label every second one (at most nine), both ends labelled.
  EXPECT_EQ(Count(svg, "class=\"legend-tick\""), 7u);
  EXPECT_TRUE(Has(svg, ">1e-12</text>") && Has(svg, ">1e-6</text>") && Has(svg, ">1e0</text>"));
  EXPECT_EQ(Count(svg, "class=\"legend-special\""), 0u);  // nothing special present, nothing listed
}

TEST(Heatmap, ZeroNanInfinityAndNegativeAreDrawnAndCounted) {
  HeatmapSpec h = Spec15();
  h.values(0, 1) = 0.0;
  h.values(2, 3) = 0.0;
  h.values(1, 2) = kNaN;
  h.values(3, 4) = kInf;
  h.values(4, 5) = -1.0;
  h.values(5, 6) = 1e-30;  // below the scale: bottom colour, and the bottom label says so
  const std::string svg = HeatmapSvg(h);
  EXPECT_EQ(Count(svg, "class=\"legend-special\""), 4u);
  // Each special value's legend entry with its count, and its cell's own colour and title.
  for (const std::string piece :
       {">0 \u00d72</text>", ">NaN \u00d71</text>", ">inf \u00d71</text>",
        ">negative \u00d71</text>", ">\u22641e-12</text>",
        "fill=\"#ff00ff\" class=\"cell\"><title>theta.y, theta.z: d = NaN</title>",
        "fill=\"#d62728\" class=\"cell\"><title>p.x, p.y: d = inf</title>",
        "fill=\"#ffffff\" class=\"cell\"><title>theta.x, theta.y: d = 0</title>"})
    EXPECT_TRUE(Has(svg, piece)) << piece;
}

TEST(Heatmap, LabelsAreEscapedAndSizesChecked) {
  HeatmapSpec h;
  h.values = Eigen::MatrixXd::Constant(6, 3, 1e-3);
  h.row_blocks = {"<script>", "a&b"};
  h.col_blocks = {"\"q'"};
  h.title = "J_bias <i>";
  const std::string svg = HeatmapSvg(h);
  EXPECT_FALSE(Has(svg, "<script>"));
  EXPECT_FALSE(Has(svg, "<i>"));
  EXPECT_TRUE(Has(svg, ">&lt;script&gt;</text>"));
  EXPECT_TRUE(Has(svg, ">a&amp;b</text>"));
  EXPECT_TRUE(Has(svg, ">&quot;q&#39;</text>"));
  EXPECT_EQ(Count(svg, "class=\"cell\""), 18u);
  h.row_blocks = {"one"};
  EXPECT_THROW(HeatmapSvg(h), std::invalid_argument);
  h.row_blocks = {"a", "b"};
  h.entry_labels = {"x", "y"};
  EXPECT_THROW(HeatmapSvg(h), std::invalid_argument);
  h.values.resize(0, 0);
  EXPECT_THROW(HeatmapSvg(h), std::invalid_argument);
}

// ---- the chart ----

TEST(Chart, LeavesOutWhatALogAxisCannotShowAndSaysSo) {
  ChartSpec c;
  c.y.log = true;
  c.series.push_back(
      {"nees", {0, 1, 2, 3, 4}, {1.0, 10.0, kNaN, -2.0, 100.0}, "#1f77b4", false, 2.0});
  c.lines.push_back({"upper <bound>", 19.0, false, "#d62728"});
  c.lines.push_back({"", 2.7, false, "#d62728"});
  const std::string out = ChartSvg(c);
  EXPECT_EQ(Count(out, "<circle cx=") - 1, 3u);  // three drawable points, less the legend's dot
  EXPECT_TRUE(Has(out, "nees (2 not drawable, left out)"));
  EXPECT_EQ(Count(out, "class=\"reference\""), 2u);
  EXPECT_TRUE(Has(out, "upper &lt;bound&gt;"));
  // Decade ticks from 1 to 100.
  EXPECT_TRUE(Has(out, ">1</text>") && Has(out, ">10</text>") && Has(out, ">100</text>"));
}

TEST(Chart, ThinningKeepsEveryExtreme) {
  ChartSpec c;
  PointSeries s{"error", {}, {}, "#1f77b4", false, 1.0};
  for (int i = 0; i < 10000; ++i) {
    s.x.push_back(i);
    s.y.push_back(std::sin(i * 0.01));
  }
  s.y[5003] = 100.0;  // one spike among 10000 points
  c.series.push_back(s);
  c.max_points = 2000;
  const std::string out = ChartSvg(c);
  const std::size_t dots = Count(out, "<circle cx=") - 1;  // less the legend's dot
  EXPECT_LE(dots, 2000u);
  EXPECT_GE(dots, 1000u);
  EXPECT_TRUE(Has(out, "of 10000 shown, extremes kept"));
  // The spike is kept: the y axis reaches 100 (ticks of 20 from -20).
  EXPECT_TRUE(Has(out, ">100</text>"));
}

TEST(Chart, BandsBarsAndMismatchedArrays) {
  ChartSpec c;
  c.bands.push_back({"\u00b13 sigma", {0, 1, 2}, {-1, -2, -3}, {1, 2, 3}, "#ff7f0e", 0.3});
  c.bars.push_back({"counts", {0, 1, 2, 3}, {4, 5, 6}, "#9ecae1"});
  const std::string out = ChartSvg(c);
  EXPECT_EQ(Count(out, "class=\"band\""), 1u);
  EXPECT_EQ(Count(out, "<g class=\"bars\""), 1u);
  c.bands[0].hi.pop_back();
  EXPECT_THROW(ChartSvg(c), std::invalid_argument);
  c.bands.clear();
  c.bars[0].edges.pop_back();
  EXPECT_THROW(ChartSvg(c), std::invalid_argument);
}

// ---- the document ----

TEST(HtmlDocument, EscapesEveryTextAndLoadsNothing) {
  HtmlDocument doc("report <for> \"x\"");
  doc.AddParagraph("<script>alert(1)</script>");
  doc.AddTable({"a<b"}, {{"c&d", "extra"}});
  doc.AddList({"<li>"});
  doc.AddCode("rm -rf <dir>");
  doc.AddFigures({{"<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>", "caption <i>"}});
  const std::string html = doc.Render();
  // Every text escaped where it stands (the table's header padded to the widest row), and a
  // policy that loads nothing.
  for (const std::string piece :
       {"&lt;script&gt;alert(1)&lt;/script&gt;", "<title>report &lt;for&gt; &quot;x&quot;</title>",
        "<th>a&lt;b</th><th></th>", "<td>c&amp;d</td>", "caption &lt;i&gt;",
        "content=\"default-src 'none'; style-src 'unsafe-inline'\""})
    EXPECT_TRUE(Has(html, piece)) << piece;
  for (const std::string piece : {"<script", "src=\"", "href=", "url("})
    EXPECT_FALSE(Has(html, piece)) << piece;
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
}

// ---- the anchored colour scale: a fixed range, the tolerance marked, calm colours within it and
// failure colours beyond it, exact zeros drawn as agreement (a dot) and not as a blank, and the
// data-scale-min/max/tolerance attributes the browser test reads ----

// "Reads as failure": red clearly dominant (orange to dark red); "calm": blue at least as strong as
// red (the pale grey-blue to blue ramp).
bool Warm(const Rgb& c) { return c.r > c.b + 40; }
bool Calm(const Rgb& c) { return c.b >= c.r; }

TEST(AnchoredScale, RoundOffIsCalmAndAFailureIsRedWhateverTheOtherValues) {
  const AnchoredScale s = AnchoredScale::Magnitude(1e-16, 1e2, 1e-2);
  // The case: round-off 1e-16 and a failure of 2 had the same top colour on a fitted scale.
  EXPECT_TRUE(Calm(s.Color(1e-16)));
  EXPECT_TRUE(Warm(s.Color(2.0)));
  EXPECT_TRUE(Calm(s.Color(1e-2)));  // the tolerance itself passes
  EXPECT_TRUE(Warm(s.Color(1.01e-2)));
  EXPECT_TRUE(s.WithinTolerance(1e-2) && !s.WithinTolerance(1.01e-2) && s.WithinTolerance(0.0));
  // Zero is exact agreement: the calm end, like the range's bottom.
  EXPECT_EQ(s.Color(0.0), s.ColorAt(0.0));
  EXPECT_EQ(s.Color(1e-16), s.ColorAt(0.0));
  EXPECT_EQ(s.Color(1e5), s.ColorAt(1.0));  // beyond the top: the end colour
  EXPECT_TRUE(s.Clamped(1e5) && s.Clamped(1e-20) && !s.Clamped(0.0) && !s.Clamped(1.0));
  // The log position: 1e-7 is halfway between 1e-16 and 1e2.
  EXPECT_NEAR(s.Position(1e-7), 0.5, 1e-12);  // log10 round-off only
  EXPECT_THROW(AnchoredScale::Magnitude(1e-2, 1e2, 1e-3), std::invalid_argument);
  EXPECT_THROW(AnchoredScale::Magnitude(0.0, 1e2, 1e-3), std::invalid_argument);
}

TEST(AnchoredScale, SignedIsCalmAroundZeroAndDarkBeyondEitherTolerance) {
  const AnchoredScale s = AnchoredScale::Signed(5.0, 3.0);
  EXPECT_EQ(s.min(), -5.0);
  EXPECT_EQ(s.Color(0.0).Hex(), "#f7f7f7");
  EXPECT_TRUE(s.WithinTolerance(-3.0) && s.WithinTolerance(3.0) && !s.WithinTolerance(3.01));
  EXPECT_TRUE(Warm(s.Color(3.5)));
  const Rgb under = s.Color(-3.5);  // beyond -tolerance: violet, blue above green
  EXPECT_TRUE(under.b > under.g + 40);
  // The calm part is light (every channel above 160), the failure part is not.
  for (double v : {-3.0, -1.0, 0.5, 3.0})
    EXPECT_GT(std::min({s.Color(v).r, s.Color(v).g, s.Color(v).b}), 160) << v;
  for (double v : {-4.5, 4.5})
    EXPECT_LT(std::min({s.Color(v).r, s.Color(v).g, s.Color(v).b}), 100) << v;
  EXPECT_THROW(AnchoredScale::Signed(3.0, 3.0), std::invalid_argument);
}

HeatmapSpec Spec6(double fill) {
  HeatmapSpec h;
  h.values = Eigen::MatrixXd::Constant(6, 6, fill);
  h.row_blocks = h.col_blocks = {"theta", "p"};
  return h;
}

/// The heatmap of `h`, whose anchored scale is stated as `scale_attributes` (the data-scale-*
/// attributes the browser test reads), marked in the legend `tolerance_marks` times and
/// counted in its label `beyond_label`.
std::string AnchoredHeatmapSvg(const HeatmapSpec& h, const std::string& scale_attributes,
                               std::size_t tolerance_marks, const std::string& beyond_label) {
  const std::string svg = HeatmapSvg(h);
  EXPECT_TRUE(Has(svg, scale_attributes));
  EXPECT_EQ(Count(svg, "class=\"legend-tolerance\""), tolerance_marks);
  EXPECT_TRUE(Has(svg, beyond_label));
  return svg;
}

TEST(AnchoredHeatmap, AttributesToleranceMarkAndCounts) {
  HeatmapSpec h = Spec6(1e-15);
  h.values(0, 0) = 2.0;
  h.values(1, 1) = 0.5;
  h.values(2, 2) = 0.0;
  h.values(3, 3) = 0.0;
  h.anchored = AnchoredScale::Magnitude(1e-16, 1e2, 1e-2);
  const std::string svg = AnchoredHeatmapSvg(
      h,
      "data-scale-kind=\"magnitude\" data-scale-min=\"1e-16\" data-scale-max=\"100\" "
      "data-tolerance=\"0.01\" data-beyond-tolerance=\"2\"",
      1u, ">2 beyond tol 0.01</text>");
  // Zeros: the calm end's colour with a dot each, listed as exact agreement; no white cell.
  EXPECT_EQ(Count(svg, "class=\"zero-mark\""), 2u);
  EXPECT_TRUE(Has(svg, ">0 (exact) \u00d72</text>"));
  EXPECT_FALSE(Has(svg, "fill=\"#ffffff\" class=\"cell\""));
  EXPECT_TRUE(Has(svg, "theta.x, theta.x: d = 2 (BEYOND the tolerance 0.01)"));
  EXPECT_TRUE(Has(svg, "fill=\"" + h.anchored->Color(2.0).Hex() + "\" class=\"cell\""));
  // The same values on another page: the same colours (the scale does not depend on them).
  HeatmapSpec other = Spec6(1e-3);
  other.values(0, 0) = 2.0;
  other.anchored = h.anchored;
  const std::string needle =
      "fill=\"" + h.anchored->Color(2.0).Hex() + "\" class=\"cell\"><title>theta.x, theta.x";
  EXPECT_TRUE(Has(HeatmapSvg(other), needle));
}

TEST(AnchoredHeatmap, SignedMarksBothTolerances) {
  HeatmapSpec h = Spec6(0.0);
  h.values(0, 0) = -4.0;
  h.values(1, 1) = 9.0;  // beyond the range: the top colour, the top label says so
  h.anchored = AnchoredScale::Signed(5.0, 3.0);
  const std::string svg = AnchoredHeatmapSvg(
      h,
      "data-scale-kind=\"signed\" data-scale-min=\"-5\" data-scale-max=\"5\" data-tolerance=\"3\"",
      2u, ">2 beyond tol \u00b13</text>");
  EXPECT_TRUE(Has(svg, ">\u22655</text>"));
  EXPECT_EQ(Count(svg, "class=\"legend-special\""), 0u);  // zeros and negatives are values here
}

TEST(HtmlDocument, VerdictBadge) {
  HtmlDocument doc("t");
  doc.AddVerdict(false, "NEES mean <16.2> outside");
  const std::string html = doc.Render();
  EXPECT_TRUE(
      Has(html,
          "<div class=\"verdict\" data-verdict=\"inconsistent\"><span class=\"verdict-word\">"
          "inconsistent</span><span class=\"verdict-reason\">NEES mean &lt;16.2&gt; "
          "outside</span></div>"));
  HtmlDocument ok("t");
  ok.AddVerdict(true, "fine");
  EXPECT_TRUE(Has(ok.Render(), "data-verdict=\"consistent\""));
}

}  // namespace
