#include "imuconv/pipeline/imu_reader.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "imuconv/pipeline/errors.h"
#include "imuconv/so3.h"

namespace imuconv::pipeline {

const std::array<const char*, 7> kImuColumnNames = {"t", "wx", "wy", "wz", "ax", "ay", "az"};

std::int64_t NanosPerUnit(TimeUnit u) {
  switch (u) {
    case TimeUnit::s: return 1000000000;
    case TimeUnit::ms: return 1000000;
    case TimeUnit::us: return 1000;
    case TimeUnit::ns: return 1;
  }
  return 1;
}

const char* TimeUnitName(TimeUnit u) {
  switch (u) {
    case TimeUnit::s: return "s";
    case TimeUnit::ms: return "ms";
    case TimeUnit::us: return "us";
    case TimeUnit::ns: return "ns";
  }
  return "?";
}

std::optional<TimeUnit> ParseTimeUnit(const std::string& s) {
  if (s == "s") return TimeUnit::s;
  if (s == "ms") return TimeUnit::ms;
  if (s == "us") return TimeUnit::us;
  if (s == "ns") return TimeUnit::ns;
  return std::nullopt;
}

namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::optional<double> ParseDouble(std::string_view s) {
  s = Trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

// Normalises whole + frac so that frac is in [0, 1).
TimeValue Normalised(std::int64_t whole, double frac) {
  const double f = std::floor(frac);
  whole += static_cast<std::int64_t>(f);
  frac -= f;
  if (frac >= 1.0) {
    whole += 1;
    frac = 0.0;
  }
  return {whole, frac};
}

}  // namespace

TimeValue TimeValueFromDouble(double t) {
  const double w = std::floor(t);
  return Normalised(static_cast<std::int64_t>(w), t - w);
}

std::optional<TimeValue> ParseTimeValue(std::string_view text) {
  std::string_view s = Trim(text);
  if (s.empty()) return std::nullopt;
  bool neg = false;
  std::string_view body = s;
  if (body.front() == '+' || body.front() == '-') {
    neg = body.front() == '-';
    body.remove_prefix(1);
  }
  const std::size_t dot = body.find('.');
  const std::string_view int_part = body.substr(0, dot);
  const std::string_view frac_part = dot == std::string_view::npos ? std::string_view() : body.substr(dot + 1);
  const auto all_digits = [](std::string_view d) {
    return std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!all_digits(int_part) || !all_digits(frac_part) || (int_part.empty() && frac_part.empty())) {
    // Not a plain decimal: an exponent form goes through double (finite values only).
    if (s.find_first_of("eE") == std::string_view::npos) return std::nullopt;
    const auto v = ParseDouble(s);
    if (!v || !std::isfinite(*v) || std::abs(*v) > 9.0e18) return std::nullopt;
    return TimeValueFromDouble(*v);
  }
  std::int64_t whole = 0;
  if (!int_part.empty()) {
    const auto r = std::from_chars(int_part.data(), int_part.data() + int_part.size(), whole);
    if (r.ec != std::errc() || r.ptr != int_part.data() + int_part.size()) return std::nullopt;  // overflow
  }
  double frac = 0.0;
  if (!frac_part.empty()) {
    const std::string f = "0." + std::string(frac_part);
    const auto r = std::from_chars(f.data(), f.data() + f.size(), frac);
    if (r.ec != std::errc()) return std::nullopt;
  }
  if (neg) return Normalised(-whole, -frac);
  return Normalised(whole, frac);
}

double TimeOrigin::relative_seconds(const TimeValue& t) const {
  std::int64_t dw = 0;
  double whole_diff;
  if (__builtin_sub_overflow(t.whole, value.whole, &dw))
    whole_diff = static_cast<double>(t.whole) - static_cast<double>(value.whole);
  else
    whole_diff = static_cast<double>(dw);
  const double units = whole_diff + (t.frac - value.frac);
  // Division by 1e9 (not multiplication by 1e-9) keeps whole nanoseconds correctly rounded.
  return units * static_cast<double>(NanosPerUnit(unit)) / 1e9;
}

std::optional<std::int64_t> TimeOrigin::nanoseconds() const {
  const std::int64_t npu = NanosPerUnit(unit);
  std::int64_t ns = 0;
  if (__builtin_mul_overflow(value.whole, npu, &ns)) return std::nullopt;
  const auto f = static_cast<std::int64_t>(std::llround(value.frac * static_cast<double>(npu)));
  if (__builtin_add_overflow(ns, f, &ns)) return std::nullopt;
  return ns;
}

std::optional<std::int64_t> TimeOrigin::absolute_ns(double relative_seconds) const {
  const auto o = nanoseconds();
  if (!o || !std::isfinite(relative_seconds) || std::abs(relative_seconds) > 9.0e9) return std::nullopt;
  std::int64_t out = 0;
  if (__builtin_add_overflow(*o, static_cast<std::int64_t>(std::llround(relative_seconds * 1e9)), &out))
    return std::nullopt;
  return out;
}

namespace {

// Streams a text file line by line, counting lines (1-based), in blocks of 64 KiB. Lines are
// capped at 1 MiB so a binary or endless file (e.g. /dev/zero) fails instead of exhausting
// memory.
class LineReader {
 public:
  static constexpr std::size_t kMaxLine = 1u << 20;
  static constexpr std::size_t kBlock = 1u << 16;
  explicit LineReader(const std::string& path) : path_(path), buf_(kBlock) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw ReadError(path, 0, "is a directory, not a file");
    in_.open(path, std::ios::binary);
    if (!in_) throw ReadError(path, 0, "cannot open the file for reading");
  }
  bool next(std::string& line) {
    line.clear();
    bool any = false;
    while (true) {
      if (pos_ == end_ && !fill()) {
        if (!any) return false;
        break;
      }
      const char* start = buf_.data() + pos_;
      const std::size_t avail = end_ - pos_;
      const auto* nl = static_cast<const char*>(std::memchr(start, '\n', avail));
      const std::size_t len = nl ? static_cast<std::size_t>(nl - start) : avail;
      // What fits under the cap is checked for NUL bytes first (as a byte-wise reader would).
      const std::size_t room = kMaxLine + 1 - line.size();
      const std::size_t take = std::min(len, room);
      if (std::memchr(start, '\0', take) != nullptr)
        throw ReadError(path_, line_no_ + 1, "contains a NUL byte; expected a text (CSV) file");
      if (len > kMaxLine - line.size())
        throw ReadError(path_, line_no_ + 1, "line is longer than 1 MiB; expected a text (CSV) file");
      line.append(start, len);
      any = true;
      pos_ += len;
      if (nl) {
        ++pos_;
        break;
      }
    }
    ++line_no_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no_ == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 BOM
    return true;
  }
  std::size_t line_no() const noexcept { return line_no_; }

 private:
  bool fill() {
    if (!in_) return false;
    in_.read(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    pos_ = 0;
    end_ = static_cast<std::size_t>(in_.gcount());
    return end_ > 0;
  }
  std::string path_;
  std::ifstream in_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  std::size_t line_no_ = 0;
};

bool IsBlank(std::string_view s) { return Trim(s).empty(); }

void Split(std::string_view line, char delim, bool whitespace, std::vector<std::string_view>& out) {
  out.clear();
  if (whitespace) {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      out.push_back(line.substr(i, j - i));
      i = j;
    }
    return;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = line.find(delim, start);
    if (pos == std::string_view::npos) {
      out.push_back(Trim(line.substr(start)));
      return;
    }
    out.push_back(Trim(line.substr(start, pos - start)));
    start = pos + 1;
  }
}

std::string Shown(std::string_view s) {
  std::string t(s.substr(0, 40));
  if (s.size() > 40) t += "...";
  return "'" + t + "'";
}

std::string DelimiterName(char d, bool ws) {
  if (ws) return "whitespace";
  if (d == '\t') return "tab";
  return std::string("'") + d + "'";
}

struct Layout {
  std::array<int, 7> index{};   // field index of t, wx, ..., az
  std::array<std::string, 7> label;  // for messages
  std::size_t n_fields = 0;     // expected number of fields per line (0: set by the first data line)
};

// The shared streaming core. `strict_count` demands exactly `layout.n_fields` fields.
ImuData ReadImuRows(const std::string& path, const CsvFormat& f, Layout layout, bool integer_time,
                    std::optional<TimeValue> origin, LineReader& lr, const char* time_what) {
  ImuData data;
  data.source = path;
  std::string line;
  std::vector<std::string_view> fields;
  std::optional<TimeValue> first_t;
  TimeOrigin org;
  org.unit = f.time_unit;
  TimeValue prev{};
  std::size_t prev_line = 0;
  const int max_index = *std::max_element(layout.index.begin(), layout.index.end());
  while (lr.next(line)) {
    if (IsBlank(line)) continue;
    if (!f.comment.empty() && Trim(line).substr(0, f.comment.size()) == f.comment) continue;
    Split(line, f.delimiter, f.whitespace_delimited, fields);
    const std::size_t ln = lr.line_no();
    if (layout.n_fields == 0) {
      layout.n_fields = fields.size();
      if (static_cast<int>(fields.size()) <= max_index)
        throw ReadError(path, ln,
                        "expected at least " + std::to_string(max_index + 1) + " fields separated by " +
                            DelimiterName(f.delimiter, f.whitespace_delimited) + " (the column map uses index " +
                            std::to_string(max_index) + "), found " + std::to_string(fields.size()));
    }
    if (fields.size() != layout.n_fields)
      throw ReadError(path, ln,
                      "expected " + std::to_string(layout.n_fields) + " fields separated by " +
                          DelimiterName(f.delimiter, f.whitespace_delimited) + ", found " +
                          std::to_string(fields.size()));
    ImuSample s;
    // Time.
    const std::string_view tf = fields[static_cast<std::size_t>(layout.index[0])];
    std::optional<TimeValue> tv;
    if (integer_time) {
      std::int64_t ns = 0;
      const std::string_view tt = Trim(tf);
      const auto r = std::from_chars(tt.data(), tt.data() + tt.size(), ns);
      if (!tt.empty() && r.ec == std::errc() && r.ptr == tt.data() + tt.size()) tv = TimeValue{ns, 0.0};
    } else {
      tv = ParseTimeValue(tf);
    }
    if (!tv)
      throw ReadError(path, ln,
                      "column " + std::to_string(layout.index[0]) + " (" + layout.label[0] + "): expected " + time_what +
                          ", found " + Shown(tf));
    if (!first_t) {
      first_t = *tv;
      org.value = origin ? *origin : *tv;
    } else if (!(tv->whole > prev.whole || (tv->whole == prev.whole && tv->frac > prev.frac))) {
      throw ReadError(path, ln,
                      "timestamp " + std::string(Trim(tf)) + " is not after the previous sample's (line " +
                          std::to_string(prev_line) + "); timestamps must be strictly increasing");
    }
    prev = *tv;
    prev_line = ln;
    s.t = org.relative_seconds(*tv);
    // Rates and specific forces.
    for (int k = 1; k < 7; ++k) {
      const std::string_view fv = fields[static_cast<std::size_t>(layout.index[k])];
      const auto v = ParseDouble(fv);
      if (!v || !std::isfinite(*v))
        throw ReadError(path, ln,
                        "column " + std::to_string(layout.index[k]) + " (" + layout.label[k] + "): expected a finite number, found " +
                            Shown(fv));
      if (k <= 3)
        s.gyro[k - 1] = *v;
      else
        s.accel[k - 4] = *v;
    }
    if (!data.samples.empty() && !(s.t > data.samples.back().t))
      throw ReadError(path, ln, "timestamp is too close to the previous sample's to be told apart in double seconds");
    data.samples.push_back(s);
  }
  if (data.samples.empty()) throw ReadError(path, 0, "contains no IMU samples");
  data.origin = org;
  return data;
}

}  // namespace

ImuData ReadEurocImu(const std::string& path, std::optional<std::int64_t> origin_ns) {
  LineReader lr(path);
  CsvFormat f;
  f.delimiter = ',';
  f.comment = "#";
  f.time_unit = TimeUnit::ns;
  Layout layout;
  layout.index = {0, 1, 2, 3, 4, 5, 6};
  layout.label = {"timestamp [ns]", "w_x", "w_y", "w_z", "a_x", "a_y", "a_z"};
  layout.n_fields = 7;
  std::optional<TimeValue> origin;
  if (origin_ns) origin = TimeValue{*origin_ns, 0.0};
  return ReadImuRows(path, f, layout, true, origin, lr, "an integer timestamp in nanoseconds");
}

ImuData ReadCsvImu(const std::string& path, const CsvFormat& f) {
  LineReader lr(path);
  Layout layout;
  std::vector<std::string> header;
  std::size_t header_line = 0;
  std::string line;
  for (int h = 0; h < f.header_rows; ++h) {
    if (!lr.next(line)) throw ReadError(path, lr.line_no(), "expected " + std::to_string(f.header_rows) + " header rows, the file ends first");
    if (h == 0) {
      header_line = lr.line_no();
      std::vector<std::string_view> names;
      Split(line, f.delimiter, f.whitespace_delimited, names);
      for (auto n : names) header.emplace_back(Trim(n));
      // A leading comment marker is not part of the first name ("#time" -> "time").
      if (!header.empty() && !f.comment.empty() && header[0].rfind(f.comment, 0) == 0)
        header[0] = std::string(Trim(header[0].substr(f.comment.size())));
      layout.n_fields = header.size();
    }
  }
  for (int k = 0; k < 7; ++k) {
    const ColumnRef& c = f.columns[static_cast<std::size_t>(k)];
    if (std::holds_alternative<int>(c)) {
      layout.index[k] = std::get<int>(c);
      if (layout.index[k] < 0) throw ReadError(path, 0, std::string("column index of '") + kImuColumnNames[k] + "' is negative");
      layout.label[k] = kImuColumnNames[k];
      if (!header.empty() && static_cast<std::size_t>(layout.index[k]) < header.size())
        layout.label[k] = std::string(kImuColumnNames[k]) + ", '" + header[static_cast<std::size_t>(layout.index[k])] + "'";
    } else {
      const std::string& name = std::get<std::string>(c);
      if (header.empty())
        throw ReadError(path, 0, std::string("column '") + kImuColumnNames[k] + "' is given by the name '" + name +
                                     "' but the format has no header row (header_rows is 0)");
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end()) {
        std::string known;
        for (const auto& hname : header) known += (known.empty() ? "'" : ", '") + hname + "'";
        throw ReadError(path, header_line,
                        std::string("no column named '") + name + "' (for '" + kImuColumnNames[k] + "') in the header; columns: " + known);
      }
      layout.index[k] = static_cast<int>(it - header.begin());
      layout.label[k] = std::string(kImuColumnNames[k]) + ", '" + name + "'";
    }
  }
  const std::string what = std::string("a timestamp in ") + TimeUnitName(f.time_unit);
  return ReadImuRows(path, f, layout, false, f.time_origin, lr, what.c_str());
}

std::optional<ImuState> GroundTruth::at(double tq) const {
  if (t.empty() || !(tq >= t.front()) || !(tq <= t.back())) return std::nullopt;
  const std::size_t i = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), tq) - t.begin());
  if (t[i] == tq) return x[i];
  const ImuState& a = x[i - 1];
  const ImuState& b = x[i];
  const double u = (tq - t[i - 1]) / (t[i] - t[i - 1]);
  ImuState s;
  s.p = a.p + u * (b.p - a.p);
  s.v = a.v + u * (b.v - a.v);
  s.bg = a.bg + u * (b.bg - a.bg);
  s.ba = a.ba + u * (b.ba - a.ba);
  // Geodesic interpolation: R_a Exp(u Log(R_a^T R_b)).
  s.R = a.R * so3::Exp(u * so3::Log(a.R.transpose() * b.R));
  return s;
}

GroundTruth ReadEurocGroundTruth(const std::string& path, const TimeOrigin& origin) {
  LineReader lr(path);
  GroundTruth gt;
  gt.source = path;
  std::string line;
  std::vector<std::string_view> fields;
  static const char* kNames[17] = {"timestamp [ns]", "p_x", "p_y", "p_z", "q_w", "q_x", "q_y", "q_z", "v_x",
                                   "v_y", "v_z", "bg_x", "bg_y", "bg_z", "ba_x", "ba_y", "ba_z"};
  const std::int64_t npu = NanosPerUnit(origin.unit);
  std::int64_t prev_ns = 0;
  std::size_t prev_line = 0;
  while (lr.next(line)) {
    if (IsBlank(line) || Trim(line).front() == '#') continue;
    const std::size_t ln = lr.line_no();
    Split(line, ',', false, fields);
    if (fields.size() != 17)
      throw ReadError(path, ln,
                      "expected 17 fields (timestamp [ns], p xyz, q wxyz, v xyz, bg xyz, ba xyz) separated by ',', found " +
                          std::to_string(fields.size()));
    std::int64_t ns = 0;
    const auto r = std::from_chars(fields[0].data(), fields[0].data() + fields[0].size(), ns);
    if (fields[0].empty() || r.ec != std::errc() || r.ptr != fields[0].data() + fields[0].size())
      throw ReadError(path, ln, "column 0 (timestamp [ns]): expected an integer timestamp in nanoseconds, found " + Shown(fields[0]));
    if (!gt.t.empty() && ns <= prev_ns)
      throw ReadError(path, ln,
                      "timestamp " + std::to_string(ns) + " is not after the previous sample's (line " +
                          std::to_string(prev_line) + "); timestamps must be strictly increasing");
    double v[17];
    for (int k = 1; k < 17; ++k) {
      const auto d = ParseDouble(fields[static_cast<std::size_t>(k)]);
      if (!d || !std::isfinite(*d))
        throw ReadError(path, ln,
                        "column " + std::to_string(k) + " (" + kNames[k] + "): expected a finite number, found " +
                            Shown(fields[static_cast<std::size_t>(k)]));
      v[k] = *d;
    }
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (std::abs(qn - 1.0) > 1e-3)
      throw ReadError(path, ln, "quaternion (q_w, q_x, q_y, q_z) has norm " + std::to_string(qn) + ", expected 1");
    ImuState s;
    s.p = Vec3(v[1], v[2], v[3]);
    s.R = so3::FromQuaternionWxyz(v[4], v[5], v[6], v[7]);
    s.v = Vec3(v[8], v[9], v[10]);
    s.bg = Vec3(v[11], v[12], v[13]);
    s.ba = Vec3(v[14], v[15], v[16]);
    // The stamp in the origin's unit, then relative to it.
    std::int64_t whole = ns / npu, rem = ns % npu;
    if (rem < 0) {
      whole -= 1;
      rem += npu;
    }
    gt.t.push_back(origin.relative_seconds(TimeValue{whole, static_cast<double>(rem) / static_cast<double>(npu)}));
    gt.x.push_back(s);
    prev_ns = ns;
    prev_line = ln;
  }
  if (gt.t.empty()) throw ReadError(path, 0, "contains no ground-truth rows");
  return gt;
}

}  // namespace imuconv::pipeline
