// imuconv merge -o OUT.json SHARD.json...: joins the N outputs of `imuconv run P.json --shard K/N`
// (given in any order) into the document `imuconv run P.json` writes, byte for byte
// (examples/batch/).
//
// The shards are read, checked and joined by pipeline/src/run/shard_merge.cpp (shard_merge.h: the
// layout, the FNV-1a 64 each shard records of its own content, what is refused); this file is
// the command: the montecarlo-shard pointer, the atomic output, never one of the shards.
//
// Refused, each with the file named (exit 2, no output written): a FIFO, a device or a directory
// (read as every input is: never waited on), a file that is not a shard, a
// truncated one, shards of different splits or of another pipeline, imuconv version, plugins,
// data (the heads before "tasks" differ) or inputs (sizes and FNV-1a hashes differ), shards
// computed by kernel instances that round differently (/shard/kernel_instance), a shard given
// twice, a missing one, one whose content does not match its /shard_fnv1a_64. A montecarlo
// shard is pointed to imuconv montecarlo --merge.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "imuconv/cli/commands.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/input_start.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/shard_merge.h"
#include "imuconv/printable.h"
#include "shard.h"

namespace imuconv::cli {
namespace {

struct MergeOptions {
  std::string output;
  std::vector<std::string> shards;
};

int Merge(const CommandContext& ctx, const MergeOptions& o) {
  for (const auto& file : o.shards) {
    // A montecarlo shard has its own merge (it concludes statistics, it does not join text). Its
    // first bytes are read as every input is: a FIFO or a device is refused, never waited on.
    std::string first;
    try {
      first = pipeline::ReadInputStart(file, montecarlo::kShardMagic.size());
    } catch (const pipeline::ReadError& e) {
      throw UsageError{std::string("merge: ") + e.what()};
    }
    if (first == montecarlo::kShardMagic)
      throw UsageError{"merge: " + Printable(file) +
                       " is a shard of imuconv montecarlo --shard K/N: join those with imuconv "
                       "montecarlo --merge"};
  }
  try {
    // First every shard is read through and checked: nothing is written before.
    const pipeline::RunShards shards = pipeline::CheckRunShards(o.shards);
    pipeline::OutputFile out(o.output);
    for (const auto& file : o.shards) out.refuse_if_same(file, "a shard");
    const std::uint64_t written =
        pipeline::JoinRunShards(shards, [&](std::string_view s) { out.write(s); });
    std::cout.flush();
    out.commit();
    if (!ctx.quiet() && !out.is_stdout())
      std::cout << "wrote " << Printable(o.output) << " (" << written << " task(s) from "
                << shards.order.size() << " shard(s))\n";
  } catch (const pipeline::ShardError& e) {
    throw UsageError{std::string("merge: ") + e.what()};
  }
  return 0;
}

}  // namespace
void RegisterMergeCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand("merge",
                                 "Join the N outputs of imuconv run P.json --shard K/N (K = "
                                 "0..N-1, in any order) into the document imuconv run "
                                 "P.json writes, byte for byte. Refused, naming the file, and "
                                 "nothing written: a missing or duplicate shard, a "
                                 "truncated one, shards of another split, pipeline, imuconv "
                                 "version, plugins or input data (examples/batch/)");
  const auto o = std::make_shared<MergeOptions>();
  AddOutputPathOption(*sub, "-o,--output", o->output,
                      "Output file (replaced atomically, as imuconv run writes it; '-' is stdout); "
                      "never one of the shards",
                      "OUT.json")
      ->required();
  sub->add_option("shards", o->shards, "The shard outputs")->required()->type_name("SHARD.json");
  SetCommandAction(*sub, ctx, [&ctx, o] { return Merge(ctx, *o); });
}

}  // namespace imuconv::cli
