// ParseJsonFile: a JSON document from a regular file of bounded size, built through
// nlohmann's SAX interface so that duplicate keys and excessive nesting are caught where they
// occur (with their JSON pointer) instead of the last duplicate silently winning.
#include <algorithm>
#include <string_view>

#include "imuconv/pipeline/json_parse.h"
#include "imuconv/printable.h"
#include "input_file.h"

namespace imuconv::pipeline {
namespace {

// Builds the DOM like nlohmann's own sax_dom_parser, and knows at every event where it is:
// one frame per open array or object. A frame's `key` is the key of the value being read in
// it, so the key of a frame's parent is the token leading to that frame: the pointer of any
// position is built only when a problem needs it.
class CheckedDomBuilder {
 public:
  CheckedDomBuilder(Checker& checker, const JsonLimits& limits) : c_(checker), limits_(limits) {}

  bool null() { return value(json(nullptr), 0); }
  bool boolean(bool b) { return value(json(b), 0); }
  bool number_integer(json::number_integer_t v) { return value(json(v), 0); }
  bool number_unsigned(json::number_unsigned_t v) { return value(json(v), 0); }
  bool number_float(json::number_float_t v, const json::string_t& /*text*/) {
    return value(json(v), 0);
  }
  bool string(json::string_t& s) {
    const std::size_t cost = kHeapString + HeapBytes(s);
    return value(json(std::move(s)), cost);
  }
  bool binary(json::binary_t& b) {  // not produced by JSON text
    const std::size_t cost = kContainer + b.size();
    return value(json::binary(std::move(b)), cost);
  }

  bool start_object(std::size_t /*unknown*/) { return open(json::value_t::object); }
  bool key(json::string_t& k) {
    Frame& f = stack_.back();
    if (f.container->contains(k))
      c_.error(PointerTo(&k),
               "duplicate key " + QuotedShort(k) + " (the last one would silently win)");
    f.key = std::move(k);
    return true;
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t /*unknown*/) { return open(json::value_t::array); }
  bool end_array() { return close(); }

  bool parse_error(std::size_t position, const std::string& /*last_token*/,
                   const nlohmann::detail::exception& ex) {
    syntax_error_ = true;
    error_position_ = position;
    error_text_ = ex.what();
    return false;
  }

  json& root() noexcept { return root_; }
  bool too_large() const noexcept { return too_large_; }
  bool syntax_error() const noexcept { return syntax_error_; }
  std::size_t error_position() const noexcept { return error_position_; }
  const std::string& error_text() const noexcept { return error_text_; }

 private:
  struct Frame {
    json* container;  // stays valid: a parent gets no new element while its child is open
    std::string key;  // objects: the key of the value being read
  };

  // Memory estimate, in bytes, of what nlohmann allocates (64-bit libstdc++, with malloc's
  // 16-byte overhead per block); checked against the measured 1.7x (numbers) to 22x ("[[],...]").
  static constexpr std::size_t kArraySlot = 32;  // 16 B json in a vector that grows by doubling
  static constexpr std::size_t kObjectSlot =
      96;  // map node: 32 B links + 32 B key + 16 B json + malloc
  static constexpr std::size_t kContainer = 48;   // the heap-allocated vector or map itself
  static constexpr std::size_t kHeapString = 48;  // a string value is a heap-allocated std::string
  // Characters beyond the short-string buffer (15) live in their own block.
  static std::size_t HeapBytes(const std::string& s) { return s.size() > 15 ? s.size() + 17 : 0; }

  // Adds the cost of one more value; false (the parse stops) once over the limit.
  bool charge(std::size_t extra) {
    std::size_t slot = 16;
    if (!stack_.empty())
      slot = stack_.back().container->is_array() ? kArraySlot
                                                 : kObjectSlot + HeapBytes(stack_.back().key);
    estimate_ += slot + extra;
    if (estimate_ <= limits_.max_memory) return true;
    too_large_ = true;
    return false;
  }

  // Where the next value goes (its pointer is PointerTo(nullptr)); returns it.
  json* place(json&& v) {
    if (stack_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    Frame& f = stack_.back();
    if (f.container->is_array()) {
      f.container->push_back(std::move(v));
      return &f.container->back();
    }
    json& slot =
        (*f.container)[f.key];  // a duplicate replaces the earlier value (and was reported)
    slot = std::move(v);
    return &slot;
  }
  bool value(json&& v, std::size_t cost) {
    if (!charge(cost)) return false;
    place(std::move(v));
    return true;
  }
  bool open(json::value_t type) {
    if (stack_.size() >= limits_.max_depth) {
      c_.error(PointerTo(nullptr), "arrays and objects are nested deeper than " +
                                       std::to_string(limits_.max_depth) + " levels");
      return false;  // ends the parse
    }
    if (!charge(kContainer)) return false;
    json* p = place(json(type));
    stack_.push_back({p, {}});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }
  // The pointer of the next value in the innermost frame, or of its member `next_key`.
  std::string PointerTo(const std::string* next_key) const {
    std::string p;
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      const Frame& f = stack_[i];
      const bool last = i + 1 == stack_.size();
      if (f.container->is_object())
        p += "/" + PointerToken(last && next_key ? *next_key : f.key);
      else  // an array: its last element leads to the next frame; a new value goes at size()
        p += "/" + std::to_string(last ? f.container->size() : f.container->size() - 1);
    }
    return p;
  }

  Checker& c_;
  JsonLimits limits_;
  std::size_t estimate_ = 0;
  bool too_large_ = false;
  json root_;
  std::vector<Frame> stack_;
  bool syntax_error_ = false;
  std::size_t error_position_ = 0;
  std::string error_text_;
};

// "parse error at line L, column C: WHAT" from the byte offset nlohmann reports and its
// exception text, without the library's "[json.exception.parse_error.101]" id. Lines and
// columns are counted as nlohmann counts them: 1-based lines, the column of the last byte read.
std::string SyntaxMessage(std::string_view text, std::size_t position, std::string what) {
  // At the end of the input nlohmann counts the end itself as one more character read.
  const std::size_t past_end = position > text.size() ? position - text.size() : 0;
  position -= past_end;
  const auto end = text.begin() + static_cast<std::ptrdiff_t>(position);
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), end, '\n'));
  const std::size_t last_nl = position == 0 ? std::string::npos : text.rfind('\n', position - 1);
  const std::size_t column =
      (last_nl == std::string::npos ? position : position - last_nl - 1) + past_end;
  if (!what.empty() && what.front() == '[') {
    const auto p = what.find("] ");
    if (p != std::string::npos) what.erase(0, p + 2);
  }
  if (what.rfind("parse error at line ", 0) == 0) {
    const auto p = what.find(": ");
    if (p != std::string::npos) what.erase(0, p + 2);
  } else if (what.rfind("parse error: ", 0) == 0) {
    what.erase(0, 13);
  }
  // The library quotes the last token read, which can be any length: 200 bytes say enough.
  if (what.size() > 200) what = what.substr(0, 200) + "...";
  return "not valid JSON: parse error at line " + std::to_string(line) + ", column " +
         std::to_string(column) + ": " + Printable(what);
}

// "256 MiB", or bytes for limits that are not whole MiB.
std::string Size(std::size_t n) {
  if (n >= (std::size_t{1} << 20) && n % (std::size_t{1} << 20) == 0)
    return std::to_string(n >> 20) + " MiB";
  return std::to_string(n) + " bytes";
}

}  // namespace

json ParseJsonFile(const std::string& path, const JsonLimits& limits) {
  const std::string text = data::ReadWholeFile(path, limits.max_bytes, Size(limits.max_bytes),
                                               ", the largest JSON document imuconv reads");
  return ParseJsonText(text, path, limits);
}

json ParseJsonText(std::string_view text, const std::string& source, const JsonLimits& limits) {
  if (text.size() > limits.max_bytes)
    throw ReadError(
        source, 0,
        "is larger than " + Size(limits.max_bytes) + ", the largest JSON document imuconv reads");
  Checker c(source);
  CheckedDomBuilder builder(c, limits);
  json::sax_parse(text.begin(), text.end(), &builder, nlohmann::detail::input_format_t::json,
                  /*strict=*/true,
                  /*ignore_comments=*/false);
  if (builder.too_large())
    throw ReadError(source, 0,
                    "would take more than " + Size(limits.max_memory) +
                        " of memory once parsed: it holds too many small values (imuconv's own "
                        "documents take about "
                        "twice their size)");
  if (builder.syntax_error())
    throw ConfigError(source,
                      {{"", SyntaxMessage(text, builder.error_position(), builder.error_text())}});
  c.throw_if_errors();  // duplicate keys, nesting
  return std::move(builder.root());
}

}  // namespace imuconv::pipeline
