// The value events JsonWriter writes in Form::kEvents: the calls a document is written with, as
// compact binary records, so that the result-array collector (array_collector.h) receives the
// output's values typed (each number the double itself, each vector and matrix whole with its
// shape) without text in between. In-process only (native byte order); internal to
// imuconv_pipeline.
//
// A record is one byte, then its payload:
//   '{' '}' '[' ']'          an object or array opens or closes
//   'k' LEN BYTES            a member name;  's' LEN BYTES  a string (LEN: 8 bytes)
//   'd' DOUBLE  'i' INT64  'u' UINT64  't' 'f' 'n'   a number, true, false, null
//   'v' N DOUBLE*N           a vector: a one-line array of N finite numbers
//   'm' R C DOUBLE*(R*C)     a matrix: R rows of C finite numbers, row by row
// A writer only ever hands whole records to the output's sink, but the replay does not rely on
// it: it consumes the whole records of a piece and leaves the rest for the next.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace imuconv::pipeline::detail {

static_assert(sizeof(double) == 8, "a 'd', 'v' or 'm' record holds 8-byte doubles");

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

/// Calls `values` (the result-array collector, array_collector.h) for each whole record at the
/// start of `events`; returns the bytes consumed.
template <typename Values>
std::size_t ReplayEvents(std::string_view events, Values& values) {
  const char* const begin = events.data();
  const char* p = begin;
  const char* const end = begin + events.size();
  const auto left = [&] { return static_cast<std::size_t>(end - p); };
  auto read = [&](auto& v) {
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
  };
  // The next number, of v's type (8 bytes: a 'd', 'i' or 'u' payload, a length); nullopt when
  // the piece ends before it (the record is then left for the next piece).
  auto take = [&](auto v) -> std::optional<decltype(v)> {
    if (left() < sizeof v) return std::nullopt;
    read(v);
    return v;
  };
  std::vector<std::size_t> shape;
  while (p < end) {
    const char* const record = p;
    const auto cut = [&] { return static_cast<std::size_t>(record - begin); };
    const char tag = *p++;
    switch (tag) {
      case '{':
        values.begin_object();
        break;
      case '}':
        values.end_object();
        break;
      case '[':
        values.begin_array();
        break;
      case ']':
        values.end_array();
        break;
      case 't':
        values.boolean(true);
        break;
      case 'f':
        values.boolean(false);
        break;
      case 'n':
        values.null();
        break;
      case 'd': {
        const auto v = take(double{});
        if (!v) return cut();
        values.real(*v);
        break;
      }
      case 'i': {
        const auto v = take(std::int64_t{});
        if (!v) return cut();
        values.integer(*v);
        break;
      }
      case 'u': {
        const auto v = take(std::uint64_t{});
        if (!v) return cut();
        values.unsigned_integer(*v);
        break;
      }
      case 'k':
      case 's': {
        const auto n = take(std::uint64_t{});
        if (!n || left() < *n) return cut();
        const std::string_view text(p, static_cast<std::size_t>(*n));
        p += *n;
        if (tag == 'k')
          values.key(text);
        else
          values.string(text);
        break;
      }
      case 'v':
      case 'm': {
        const int rank = tag == 'v' ? 1 : 2;
        if (left() < 8u * rank) return cut();
        shape.resize(static_cast<std::size_t>(rank));
        std::uint64_t count = 1;
        for (std::size_t& e : shape) {
          std::uint64_t d;
          read(d);
          e = static_cast<std::size_t>(d);
          count *= d;
        }
        if (left() / 8 < count) return cut();
        values.reals(p, shape);
        p += 8 * count;
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
