// libFuzzer target: the readers of shard files. The first byte picks which (the seeds start with
// 'P' or 'M'): even, the rest is a shard of `imuconv run --shard K/N` checked and joined as
// `imuconv merge` does (CheckRunShards, JoinRunShards: the "shard" member through the one JSON
// reader, the element scan, the FNV-1a 64 of /shard_fnv1a_64, the counts against the file's
// size); odd, a shard of `imuconv montecarlo --shard K/N` read and concluded as
// `imuconv montecarlo --merge` does (header line, payload, hash line, statistics).
#include <string_view>

#include "fuzz_support.h"
#include "imuconv/pipeline/shard_merge.h"
#include "shard.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace imuconv;
  static fuzz::InputFile file("shard");
  if (size == 0) return 0;
  const std::string& path = file.write(data + 1, size - 1);
  if ((data[0] & 1) == 0) {
    fuzz::Expect(
        [&] {
          const pipeline::RunShards shards = pipeline::CheckRunShards({path});
          // The joined document is at most the shard's size (its "shard" member and last member
          // dropped): more would be memory or time not bounded by the input.
          std::size_t joined = 0;
          pipeline::JoinRunShards(shards, [&](std::string_view s) { joined += s.size(); });
          if (joined > size)
            fuzz::InputFile::Finding("the merge wrote more bytes than the shard holds");
        },
        path);
  } else {
    fuzz::Expect(
        [&] {
          std::string case_path;
          montecarlo::MergeShards({path}, case_path);
        },
        path);
  }
  return 0;
}
