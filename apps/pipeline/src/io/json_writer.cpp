#include "imuconv/pipeline/json_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "imuconv/utf8.h"
#include "number_format.h"
#include "value_events.h"

namespace imuconv::pipeline {

namespace {

// An integer as its value event (Form::kEvents, tagged `tag`) or as its decimal text: what
// integer() and unsigned_integer() write, for their two types.
template <typename Int>
void AppendInteger(std::string& out, bool events, char tag, Int v) {
  if (events) {
    detail::PutEventScalar(out, tag, v);
    return;
  }
  char buf[24];  // 20 digits and a sign at the most
  out.append(buf, static_cast<std::size_t>(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
}

constexpr char kSpaces[] =
    "                                                                ";  // 64

void AppendPad(std::string& out, int level) {
  std::size_t n = 2 * static_cast<std::size_t>(std::max(level, 0));
  while (n > 0) {
    const std::size_t k = std::min<std::size_t>(n, sizeof kSpaces - 1);
    out.append(kSpaces, k);
    n -= k;
  }
}

// The texts of recently formatted doubles, by their bits, per thread. Covariances are symmetric
// and Jacobians repeat entries: of the nonzero numbers of examples/euroc_v1_01_full.json's
// output, 40 % were written a few hundred numbers earlier (a 512-entry table finds them), and a
// look-up costs a few instructions where std::to_chars costs some 400. The text is the one
// FormatShortest wrote for the same bits, so the output is unchanged.
struct FormatMemo {
  struct Entry {
    std::uint64_t bits;  // 0 (+0.0) never matches: zeros are written before the look-up
    std::uint8_t size;
    char text[kMaxDoubleChars];
  };
  static constexpr int kBits = 9;
  Entry entries[1 << kBits];
};
thread_local FormatMemo g_format_memo;

// Shortest round-trip form, as nlohmann::json lays it out (integral values get ".0").
inline char* FormatDouble(char* p, double v) {
  if (v == 0.0) {  // a third of a typical output (block-sparse Jacobians and covariances)
    if (std::signbit(v)) *p++ = '-';
    std::memcpy(p, "0.0", 3);
    return p + 3;
  }
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  FormatMemo::Entry& e =
      g_format_memo.entries[(bits * 0x9E3779B97F4A7C15ull) >> (64 - FormatMemo::kBits)];
  if (e.bits == bits) {
    std::memcpy(p, e.text, kMaxDoubleChars);  // the whole slot: p has room for kMaxDoubleChars
    return p + e.size;
  }
  char* const end = FormatShortest(p, v);
  e.bits = bits;
  e.size = static_cast<std::uint8_t>(end - p);
  std::memcpy(e.text, p, e.size);
  return end;
}

// JSON string literal of s (quotes and escapes), as nlohmann::json writes it. Returns the offset
// of the first byte that is not well-formed UTF-8 (then `out` holds a partial literal and the
// caller throws), or npos.
std::size_t AppendJsonString(std::string& out, std::string_view s) {
  out.push_back('"');
  std::size_t run = 0;  // start of the pending run of plain bytes
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      const std::size_t len = Utf8SequenceLength(s, i);
      if (len == 0) return i;
      i += len - 1;
      continue;
    }
    if (c >= 0x20 && c != '"' && c != '\\') continue;
    out.append(s.data() + run, i - run);
    run = i + 1;
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default: {
        static const char* hex = "0123456789abcdef";
        const char u[6] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 15]};
        out.append(u, 6);
      }
    }
  }
  out.append(s.data() + run, s.size() - run);
  out.push_back('"');
  return std::string_view::npos;
}

}  // namespace

JsonWriter::JsonWriter(std::string& out, int depth, std::string pointer, NonFinite non_finite,
                       Form form)
    : out_(out),
      depth_(depth),
      pointer_(std::move(pointer)),
      non_finite_(non_finite),
      form_(form),
      events_(form == Form::kEvents) {
  stack_.reserve(16);
}

int JsonWriter::content_depth() const noexcept { return depth_ + open_lines_; }

std::string JsonWriter::pointer_upto(std::size_t frames) const {
  std::string p = pointer_;
  for (std::size_t i = 0; i < frames && i < stack_.size(); ++i) {
    const Frame& f = stack_[i];
    if (f.object)
      p += "/" + PointerToken(f.key);
    else
      p += "/" + std::to_string(f.count == 0 ? 0 : f.count - 1);
  }
  return p;
}

std::string JsonWriter::container_pointer() const {
  return pointer_upto(stack_.empty() ? 0 : stack_.size() - 1);
}

std::string JsonWriter::pointer() const { return pointer_upto(stack_.size()); }

void JsonWriter::not_utf8(std::string_view s, std::size_t at, const std::string& where) const {
  throw Error(
      "would write a string that is not UTF-8 (output " + Printable(where) + ", byte " +
      std::to_string(at) + " of " + Quoted(s) +
      "), which JSON text cannot hold; it comes from an input (a file's name, a plugin's id or "
      "version?); no output is written");
}

void JsonWriter::non_finite() const {
  throw Error("produced a non-finite number (output " + pointer() + "); no output is written");
}

void JsonWriter::before_value() {
  if (stack_.empty()) return;
  Frame& f = stack_.back();
  if (f.object) return;  // key() wrote the separator
  if (events_) {
  } else if (f.one_line) {
    if (f.count) out_ += ", ";
  } else {
    out_ += f.count ? ",\n" : "\n";
    AppendPad(out_, content_depth());
  }
  ++f.count;
}

void JsonWriter::open(bool object, bool one_line, char c) {
  before_value();
  out_.push_back(c);  // the text's bracket is also the event's tag
  Frame f;
  f.object = object;
  f.one_line = one_line;
  stack_.push_back(std::move(f));
  if (!one_line) ++open_lines_;
}

void JsonWriter::close(char c) {
  const Frame f = std::move(stack_.back());
  stack_.pop_back();
  if (!f.one_line) {
    --open_lines_;
    if (f.count && !events_) {
      out_.push_back('\n');
      AppendPad(out_, content_depth());
    }
  }
  out_.push_back(c);
}

void JsonWriter::begin_object() { open(true, false, '{'); }
void JsonWriter::end_object() { close('}'); }
void JsonWriter::begin_array() { open(false, false, '['); }
void JsonWriter::begin_line_array() { open(false, true, '['); }
void JsonWriter::end_array() { close(']'); }

void JsonWriter::key(std::string_view k) {
  Frame& f = stack_.back();
  std::size_t bad = std::string_view::npos;
  if (events_) {
    bad = FirstInvalidUtf8(k);
    if (bad == std::string_view::npos) detail::PutEventString(out_, 'k', k);
  } else {
    out_ += f.count ? ",\n" : "\n";
    AppendPad(out_, content_depth());
    bad = AppendJsonString(out_, k);
    out_ += ": ";
  }
  if (bad != std::string_view::npos) not_utf8(k, bad, container_pointer() + "/" + PointerToken(k));
  ++f.count;
  f.key.assign(k.data(), k.size());
}

void JsonWriter::append_number(double v) {
  if (!std::isfinite(v)) {
    if (non_finite_ == NonFinite::Throw) non_finite();
    if (events_)
      out_.push_back('n');
    else
      out_ += "null";
    return;
  }
  if (events_) {
    detail::PutEventScalar(out_, 'd', v);
    return;
  }
  char buf[40];
  out_.append(buf, static_cast<std::size_t>(FormatDouble(buf, v) - buf));
}

void JsonWriter::number(double v) {
  before_value();
  append_number(v);
}

void JsonWriter::integer(std::int64_t v) {
  before_value();
  AppendInteger(out_, events_, 'i', v);
}

void JsonWriter::unsigned_integer(std::uint64_t v) {
  before_value();
  AppendInteger(out_, events_, 'u', v);
}

void JsonWriter::boolean(bool b) {
  before_value();
  if (events_)
    out_.push_back(b ? 't' : 'f');
  else
    out_ += b ? "true" : "false";
}

void JsonWriter::string(std::string_view s) {
  before_value();
  std::size_t bad = std::string_view::npos;
  if (events_) {
    bad = FirstInvalidUtf8(s);
    if (bad == std::string_view::npos) detail::PutEventString(out_, 's', s);
  } else {
    bad = AppendJsonString(out_, s);
  }
  if (bad != std::string_view::npos) not_utf8(s, bad, pointer());
}

void JsonWriter::null() {
  before_value();
  if (events_)
    out_.push_back('n');
  else
    out_ += "null";
}

void JsonWriter::numbers(const double* v, std::size_t n) {
  before_value();
  // The array one number() at a time, inside its own one-line frame: what the fast paths below
  // fall back to, so that a non-finite element is named or nulled as number() does it.
  const auto by_element = [&] {
    stack_.push_back(Frame{false, true, 0, {}});
    out_.push_back('[');
    for (std::size_t i = 0; i < n; ++i) number(v[i]);
    out_.push_back(']');
    stack_.pop_back();
  };
  if (events_) {
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) finite = finite && std::isfinite(v[i]);
    if (finite) {
      detail::PutEventScalar<std::uint64_t>(out_, 'v', n);
      detail::PutEventBytes(out_, v, 8 * n);
      return;
    }
    // As the text does: the pointer of the first non-finite element, or null in its place.
    by_element();
    return;
  }
  // One formatting pass into a local buffer, one append.
  char buf[32 * 28 + 4];
  if (n > 32) {
    by_element();
    return;
  }
  char* p = buf;
  *p++ = '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      if (non_finite_ == NonFinite::Throw) {
        stack_.push_back(Frame{false, true, i + 1, {}});  // so that pointer() names the element
        non_finite();
      }
      if (i) {
        *p++ = ',';
        *p++ = ' ';
      }
      std::memcpy(p, "null", 4);
      p += 4;
      continue;
    }
    if (i) {
      *p++ = ',';
      *p++ = ' ';
    }
    p = FormatDouble(p, v[i]);
  }
  *p++ = ']';
  out_.append(buf, static_cast<std::size_t>(p - buf));
}

bool JsonWriter::whole_matrix(const double* v, std::size_t rows, std::size_t cols) {
  for (std::size_t i = 0; i < rows * cols; ++i)
    if (!std::isfinite(v[i])) return false;
  before_value();
  detail::PutEventScalar<std::uint64_t>(out_, 'm', rows);
  const std::uint64_t c = cols;
  detail::PutEventBytes(out_, &c, sizeof c);
  detail::PutEventBytes(out_, v, 8 * rows * cols);
  return true;
}

void JsonWriter::string_list(const std::vector<std::string>& v) {
  begin_line_array();
  for (const auto& s : v) string(s);
  end_array();
}

namespace {
bool IsScalar(const json& j) { return !j.is_object() && !j.is_array(); }
}  // namespace

void JsonWriter::value(const json& j) {
  switch (j.type()) {
    case json::value_t::object:
      begin_object();
      for (auto it = j.begin(); it != j.end(); ++it) {
        key(it.key());
        value(it.value());
      }
      end_object();
      return;
    case json::value_t::array:
      if (std::all_of(j.begin(), j.end(), IsScalar))
        begin_line_array();
      else
        begin_array();
      for (const auto& e : j) value(e);
      end_array();
      return;
    case json::value_t::number_float:
      number(j.get<double>());
      return;
    case json::value_t::number_integer:
      integer(j.get<std::int64_t>());
      return;
    case json::value_t::number_unsigned:
      unsigned_integer(j.get<std::uint64_t>());
      return;
    case json::value_t::boolean:
      boolean(j.get<bool>());
      return;
    case json::value_t::string:
      string(j.get_ref<const std::string&>());
      return;
    default:
      null();
      return;
  }
}

std::string JsonWriter::element_separator(bool first) const {
  if (events_) return {};
  std::string sep = (first && stack_.back().count == 0) ? "\n" : ",\n";
  AppendPad(sep, content_depth());
  return sep;
}

void JsonWriter::skip_elements(std::size_t n) { stack_.back().count += n; }

}  // namespace imuconv::pipeline
