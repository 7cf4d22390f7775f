// FNV-1a 64 of bytes and of files: how the shards of `imuconv run --shard K/N` and of
// `imuconv montecarlo --shard K/N` record their inputs, and how a montecarlo shard checks its own
// bytes, so that a merge tells shards made from other inputs, or damaged ones, apart. It
// detects an accident, not a forgery.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace imuconv::pipeline {

/// The running FNV-1a 64 hash of the bytes added so far.
class Fnv1a64 {
 public:
  void add(const char* bytes, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      value_ ^= static_cast<unsigned char>(bytes[i]);
      value_ *= 1099511628211ull;  // FNV's 64-bit prime
    }
  }
  std::uint64_t value() const { return value_; }
  /// 16 lower-case hexadecimal digits.
  std::string hex() const;

 private:
  std::uint64_t value_ = 14695981039346656037ull;  // FNV-1a's 64-bit offset basis
};

/// A file's size and hash.
struct FileDigest {
  std::uint64_t bytes = 0;
  Fnv1a64 hash;
};

/// Reads `file` to its end. Throws ReadError naming it when it cannot be opened or read to the
/// end ("... to record its hash in the shard").
FileDigest DigestFile(const std::string& file);

}  // namespace imuconv::pipeline
