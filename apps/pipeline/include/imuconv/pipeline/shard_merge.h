// Reading and joining the documents of `imuconv run P.json --shard K/N` (the shard layout:
// schemas/output.schema.json, "shard" and "shard_fnv1a_64"; examples/batch/): `imuconv merge`
// and the fuzz target fuzz_shard use it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"

namespace imuconv::pipeline {

/// A shard that cannot be merged, or shards that do not make one run: what() names the file
/// (or both files) and what was expected.
class ShardError : public Error {
 public:
  using Error::Error;
};

/// What a shard says of itself, and its text up to its first task element.
struct ShardHead {
  std::string file;
  std::string shard_text, head;  ///< the "shard" member's value; the head through "tasks": [
  bool head_as_first = false;    ///< the head is the first shard's (then not kept twice)
  json shard;
  std::uint64_t index = 0, count = 0, tasks = 0, first = 0, end = 0;
};

/// Shards read through and checked, in shard order.
struct RunShards {
  std::vector<ShardHead> heads;    ///< as given
  std::vector<std::size_t> order;  ///< indices into heads, shard 0 first
};

/// Reads every file through once: its "shard" member, its head, every element, and checks the
/// FNV-1a 64 in its last member; then that together they are every shard of one run, once
/// (same split, inputs, kernel instance, head; none missing or twice; tasks contiguous). Memory:
/// each shard's head and "shard" member (bounded), never its elements. Throws ShardError.
RunShards CheckRunShards(const std::vector<std::string>& files);

/// The shards of a run split `count` ways that are not among the `given` ones (`is_given`
/// says which index is), for the message that refuses them: "missing M of the N shards (index
/// i, j, ...)", the first 20 indices listed (a split a million ways must not make a message of
/// megabytes); "" when none is missing. imuconv run's shards and imuconv montecarlo's are
/// refused in these words.
[[nodiscard]] std::string MissingShards(std::uint64_t count, std::uint64_t given,
                                        const std::function<bool(std::uint64_t)>& is_given);

/// Writes the whole run's document, byte for byte what `imuconv run P.json` writes, through
/// `write`, reading each shard again (and refusing, with ShardError, one that changed since it
/// was checked: the caller's output must then be discarded). Returns the number of task elements.
std::uint64_t JoinRunShards(const RunShards& shards,
                            const std::function<void(std::string_view)>& write);

}  // namespace imuconv::pipeline
