// What a forger (or a tool editing a shard on purpose) does: change a shard's bytes and write
// the hash its format records to match, so that a test reaches the checks behind the hash.
// FNV-1a 64 is written here from its definition (offset basis 14695981039346656037, prime
// 1099511628211), independently of imuconv's pipeline/file_digest.h.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace imuconv::test {

inline std::string Fnv1a64Hex(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

/// The forger's edit: the first `key` in `text` replaced by `value`. False, and `text`
/// unchanged, where `text` has no `key` (the test then forges nothing and must say so).
inline bool ReplaceFirst(std::string& text, const std::string& key, const std::string& value) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return false;
  text.replace(at, key.size(), value);
  return true;
}

/// A shard of `imuconv run --shard K/N` with its last member "shard_fnv1a_64" rewritten to the
/// hash of everything before ",\n  \"shard_fnv1a_64\"" (the bracket closing "tasks" included).
/// Returns "" when the text has no such member.
inline std::string ResealRunShard(const std::string& text) {
  const std::string member = ",\n  \"shard_fnv1a_64\": \"";
  const std::size_t at = text.rfind(member);
  if (at == std::string::npos || text.size() < at + member.size() + 16) return "";
  std::string out = text;
  out.replace(at + member.size(), 16, Fnv1a64Hex(text.substr(0, at)));
  return out;
}

/// A shard of `imuconv montecarlo --shard K/N` with its last line "fnv1a_64 <hex>\n" rewritten
/// to the hash of everything before it.
inline std::string ResealMontecarloShard(const std::string& text) {
  const std::size_t trailer = 9 + 16 + 1;  // "fnv1a_64 " + 16 hex digits + "\n"
  if (text.size() < trailer) return "";
  const std::string body = text.substr(0, text.size() - trailer);
  return body + "fnv1a_64 " + Fnv1a64Hex(body) + "\n";
}

}  // namespace imuconv::test
