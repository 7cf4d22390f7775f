// A montecarlo run split across processes or machines (docs/montecarlo.md, "Across machines"):
// `imuconv montecarlo ... --shard K/N -o FILE` runs trials [K T / N, (K+1) T / N) of the T and
// writes them to a shard file; `imuconv montecarlo --merge FILE...` checks that the N files are
// one run's, all of it once, and concludes it as the whole run does (montecarlo.h, Conclude).
//
// The shard file, in this order:
//   1. the line "imuconv montecarlo shard 1" (the format and its version);
//   2. one line of JSON: {"shard": {"index", "count", "first_trial", "end_trial"},
//      "run": {...everything that identifies the run and everything of the result that is not
//      the statistics...}, "payload_bytes"}; doubles as C99 hexadecimal floats ("%a"), which
//      read back bit for bit;
//   3. the trials' end errors, 15 IEEE-754 binary64 numbers per trial in trial order,
//      little-endian (whatever the host), 120 bytes a trial;
//   4. the line "fnv1a_64 <16 hex digits>": FNV-1a 64 of everything before it, so that a
//      corrupted file is told from a valid one (an accident, not a forgery, is what it detects).
// Every "run" object of one run's shards is the same JSON value; that is the check that they
// belong together (seed, trials, case file's name, size and hash, method, convention, plugin
// files and versions, imuconv version, the predicted covariance's bits, ...).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "montecarlo.h"

namespace imuconv::montecarlo {

/// Trials [first, end) of shard `index` of `count` of `trials`: [index T / count, (index+1) T /
/// count) rounded down, so that the shards are contiguous and differ in size by at most one trial
/// (and some are empty when count > T).
std::pair<int, int> ShardTrials(int trials, int index, int count);

/// What a shard file says of itself (its line 2).
struct ShardHeader {
  std::string file;  ///< where it was read from
  int index = 0, count = 0, first = 0, end = 0;
  nlohmann::json run;                ///< the identity, compared whole across shards
  std::uint64_t payload_offset = 0;  ///< where its errors begin in the file
};

/// Where a shard's trials came from, beyond the run's options: the imuconv version, the case
/// file (path, size, FNV-1a 64), the method's and the convention's plugin files and versions,
/// and the preintegration kernel's instance this CPU runs (baseline, avx2, avx512: a trial's
/// last bits depend on it, FMA or not), so that shards from CPUs that would round differently
/// are refused by the merge instead of merged to bytes no one run gives. Throws Error naming
/// the case file if it cannot be read.
nlohmann::json ShardProvenance(const Registry& reg, const PreintegrationMethod& method,
                               const std::string& convention, const std::string& case_path);

/// The "run" object for `head` (a RunTrials result) and its provenance: one JSON object.
nlohmann::json ShardRunJson(const Result& head, const nlohmann::json& provenance);

/// The result (all but its statistics, which Conclude computes) a "run" object describes.
/// Throws Error naming the JSON pointer under /run that is missing or malformed.
Result ResultFromRunJson(const nlohmann::json& run);

/// Writes a whole shard file through `sink` (called with pieces of at most 64 KiB).
void WriteShard(const std::function<void(std::string_view)>& sink, int index, int count, int first,
                int end, const nlohmann::json& run, const std::vector<Vec15>& errors);

/// Reads and checks a shard's first two lines and its size against them. Throws Error starting
/// with the file's name: not a shard, an unknown version, a malformed header, a truncated file
/// or one with bytes after its end.
ShardHeader ReadShardHeader(const std::string& file);

/// Reads the shard's end errors into out[0 .. end - first) and checks its hash (and that its two
/// first lines are still the ones `h` was read from). Throws Error naming the file.
void ReadShardErrors(const ShardHeader& h, Vec15* out);

/// Joins the shards of one run, in any order, into its result as the whole run computes it:
/// every shard K of the same N once, every "run" object the same. `case_path` gets the case file
/// the run was made from (for the report). Throws Error naming the file, or both files, at fault.
Result MergeShards(const std::vector<std::string>& files, std::string& case_path);

/// The first line of a shard file, without its newline.
constexpr std::string_view kShardMagic = "imuconv montecarlo shard 1";

}  // namespace imuconv::montecarlo
