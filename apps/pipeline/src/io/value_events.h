// The value events JsonWriter writes in Form::kEvents: the calls a document is written with, as
// compact binary records, so that the result-array collector (sax_collector.h) receives the
// output's values (each number the double itself) without text in between. In-process only
// (native byte order); internal to imuconv_pipeline.
//
// A record is one byte, then its payload:
//   '{' '}' '[' ']'          an object or array opens or closes
//   'k' LEN BYTES            a member name;  's' LEN BYTES  a string (LEN: 8 bytes)
//   'd' DOUBLE  'i' INT64  'u' UINT64  't' 'f' 'n'   a number, true, false, null
//   'v' N DOUBLE*N           a one-line array of N finite numbers (a vector, a matrix row)
// A writer only ever hands whole records to the output's sink, but the replay does not rely on
// it: it consumes the whole records of a piece and leaves the rest for the next.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace imuconv::pipeline::detail {

static_assert(sizeof(double) == 8, "a 'd' or 'v' record holds 8-byte doubles");

inline void PutEventBytes(std::string& out, const void* p, std::size_t n) {
  out.append(static_cast<const char*>(p), n);
}

template <typename T>
inline void PutEventScalar(std::string& out, char tag, T v) {
  char rec[1 + sizeof(T)];
  rec[0] = tag;
  std::memcpy(rec + 1, &v, sizeof(T));
  out.append(rec, sizeof rec);
}

inline void PutEventString(std::string& out, char tag, std::string_view s) {
  PutEventScalar<std::uint64_t>(out, tag, s.size());
  out.append(s.data(), s.size());
}

/// Whether `Sax` takes a 'v' record's numbers at once: `number_row(bytes, n)` for the n doubles
/// between its start_array(n) and end_array(), the same as n calls of number_float.
template <typename Sax, typename = void>
struct TakesNumberRows : std::false_type {};
template <typename Sax>
struct TakesNumberRows<Sax, std::void_t<decltype(std::declval<Sax&>().number_row(
                                static_cast<const char*>(nullptr), std::size_t{0}))>>
    : std::true_type {};

/// Calls `sax` (nlohmann::json's SAX interface) for each whole record at the start of `events`;
/// returns the bytes consumed. A 'v' record is start_array, its numbers, end_array.
template <typename Sax>
std::size_t ReplayEvents(std::string_view events, Sax& sax) {
  const char* const begin = events.data();
  const char* p = begin;
  const char* const end = begin + events.size();
  auto has = [&](std::size_t n) { return static_cast<std::size_t>(end - p) >= n; };
  auto read = [&](auto& v) {
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
  };
  std::string text;
  while (p < end) {
    const char* const record = p;
    const char tag = *p++;
    switch (tag) {
      case '{':
        sax.start_object(std::size_t(-1));
        break;
      case '}':
        sax.end_object();
        break;
      case '[':
        sax.start_array(std::size_t(-1));
        break;
      case ']':
        sax.end_array();
        break;
      case 't':
        sax.boolean(true);
        break;
      case 'f':
        sax.boolean(false);
        break;
      case 'n':
        sax.null();
        break;
      case 'd': {
        if (!has(8)) return static_cast<std::size_t>(record - begin);
        double v;
        read(v);
        sax.number_float(v, text);
        break;
      }
      case 'i': {
        if (!has(8)) return static_cast<std::size_t>(record - begin);
        std::int64_t v;
        read(v);
        sax.number_integer(v);
        break;
      }
      case 'u': {
        if (!has(8)) return static_cast<std::size_t>(record - begin);
        std::uint64_t v;
        read(v);
        sax.number_unsigned(v);
        break;
      }
      case 'k':
      case 's': {
        std::uint64_t n;
        if (!has(8)) return static_cast<std::size_t>(record - begin);
        read(n);
        if (!has(n)) return static_cast<std::size_t>(record - begin);
        text.assign(p, n);
        p += n;
        if (tag == 'k')
          sax.key(text);
        else
          sax.string(text);
        break;
      }
      case 'v': {
        std::uint64_t n;
        if (!has(8)) return static_cast<std::size_t>(record - begin);
        read(n);
        if (!has(8 * n)) return static_cast<std::size_t>(record - begin);
        sax.start_array(n);
        if constexpr (TakesNumberRows<Sax>::value) {
          sax.number_row(p, static_cast<std::size_t>(n));
          p += 8 * n;
          sax.end_array();
          break;
        }
        for (std::uint64_t i = 0; i < n; ++i) {
          double v;
          read(v);
          sax.number_float(v, text);
        }
        sax.end_array();
        break;
      }
      default:
        throw std::logic_error("value events: unknown record " +
                               std::to_string(static_cast<int>(tag)));
    }
  }
  return events.size();
}

}  // namespace imuconv::pipeline::detail
