// Reading a JSON document, from a file or a text, within limits (size, memory, nesting), with
// duplicate keys refused: the one JSON reader imuconv has (src/io/json_parse.cpp). Its errors
// are ConfigError and ReadError (errors.h); a whole file read as one form goes through a
// Checker (json_check.h), which is below this header, not beside it.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include "imuconv/pipeline/json_check.h"

namespace imuconv::pipeline {

/// Largest JSON document ParseJsonFile reads: 256 MiB. imuconv's own largest outputs must stay
/// readable as measurement files (the whole-file V1_01 run writes 34 MB).
inline constexpr std::size_t kMaxJsonBytes = std::size_t{256} << 20;
/// Largest estimated memory of a parsed document: 1 GiB. nlohmann's DOM takes 1.7 times the
/// text for imuconv's outputs (mostly numbers with many digits; 59 MB for the 34 MB output),
/// but up to 22 times for many tiny values ("[[],[],...]": 16 B of json plus a 24 B vector
/// per 3 bytes of text). The builder adds up an estimate as it goes and stops at this bound,
/// so a hostile document costs at most about 256 MiB of text + 1 GiB, while any imuconv
/// output under the size limit (<= 256 MiB x 1.7) passes.
inline constexpr std::size_t kMaxJsonMemory = std::size_t{1} << 30;
/// Deepest nesting of arrays and objects accepted (imuconv's documents nest < 10 deep; a
/// limit keeps recursive code over the document safe from a stack overflow).
inline constexpr std::size_t kMaxJsonDepth = 256;

struct JsonLimits {
  std::size_t max_bytes = kMaxJsonBytes;
  std::size_t max_memory = kMaxJsonMemory;
  std::size_t max_depth = kMaxJsonDepth;
};

/// Parses a JSON file. Regular files only (a FIFO or a device is refused without blocking),
/// within `limits`. Throws ReadError if the file cannot be read or exceeds the size or memory
/// limit, and ConfigError for a syntax error (file, line and column; pointer ""), for each
/// duplicate key (at its pointer: with nlohmann the last one would silently win), or for
/// nesting deeper than max_depth (at the pointer where it happens).
[[nodiscard]] json ParseJsonFile(const std::string& path, const JsonLimits& limits = {});

/// The one JSON reader every document imuconv reads goes through (ParseJsonFile, the shards of
/// imuconv run and imuconv montecarlo, ...): `text` read from `source` (named in every
/// message), with the same limits (size, memory, nesting depth), duplicate keys refused and the
/// same errors as ParseJsonFile.
[[nodiscard]] json ParseJsonText(std::string_view text, const std::string& source,
                                 const JsonLimits& limits = {});

/// A whole file read as one form: ParseJsonFile, then `read` (a form's reader, Node ->
/// std::optional<T>, reporting at pointers) on the document. Throws ConfigError naming the
/// file and every pointer reported, else returns the value.
template <class Read>
[[nodiscard]] auto ReadJsonFileAs(const std::string& path, Read read) {
  const json j = ParseJsonFile(path);
  Checker c(path);
  auto value = read(Node(j, "", c));
  // A reader returns nothing only after reporting why; should one not, the file is still
  // refused (never a default value given in silence).
  if (!value && c.count() == 0) c.error("", "could not be read as expected");
  c.throw_if_errors();
  return std::move(*value);
}

}  // namespace imuconv::pipeline
