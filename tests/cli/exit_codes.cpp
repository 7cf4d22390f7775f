// One exit-code table for every subcommand (apps/exit_codes.h, docs/exit-codes.md): each
// subcommand given a bad input exits 2 with a message naming it, every --help prints the
// table, an incomplete installation is an internal error (3), and a mistyped subcommand, flag
// or plugin id is answered with the nearest known ones.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

const char* const kSubcommands[] = {"plugins",    "conversion", "convert",   "run",
                                    "merge",      "refcase",    "bench",     "check",
                                    "montecarlo", "nees",       "experiment"};

TEST(ExitCodes, EveryHelpPrintsTheTable) {
  const TempDir tmp;
  std::vector<std::string> args{"--help"};
  for (const char* s : kSubcommands) args.push_back(std::string(s) + " --help");
  for (const auto& a : args) {
    const CommandResult r = RunImuconv(a, tmp);
    EXPECT_EQ(r.exit_code, 0) << a << r.err;
    EXPECT_TRUE(
        Has(r.out, "Exit codes (every command): 0 ok, or consistent; 1 judged inconsistent") &&
        Has(r.out, "2 bad input") && Has(r.out, "3 internal error") &&
        Has(r.out, "docs/exit-codes.md"))
        << a << "\n"
        << r.out;
  }
}

TEST(ExitCodes, EverySubcommandExits2OnBadInput) {
  const TempDir tmp;
  const std::string missing = ShellQuote(tmp.file("missing.json"));
  const std::string state = ShellQuote(SourcePath("examples/hover.state.json"));
  const std::string not_json = ShellQuote(tmp.write("not_json.json", "{ this is not JSON"));
  const std::string smooth = ShellQuote(DataPath("reference/cases/smooth-0.json"));
  // Each: the arguments, and a piece of the message that names what is wrong.
  const std::vector<std::pair<std::string, std::string>> cases{
      {"plugins --bogus", "--bogus"},
      {"conversion --from left --to no_such_chart --state " + state, "no_such_chart"},
      // convert exited 1 here before the table (check, nees and montecarlo exited 2).
      {"convert --what jacobian --from left --to no_such_chart --state " + state, "no_such_chart"},
      {"convert --what jacobian --from left --to gtsam_navstate --state " + missing,
       "missing.json"},
      {"run " + missing + " -o " + ShellQuote(tmp.file("o.json")), "missing.json"},
      {"run " + not_json + " -o " + ShellQuote(tmp.file("o.json")), "not_json.json"},
      {"merge -o " + ShellQuote(tmp.file("m.json")) + " " + not_json, "not_json.json"},
      {"refcase " + not_json + " -o " + ShellQuote(tmp.file("r.json")), "not_json.json"},
      {"bench --bogus", "--bogus"},
      {"check " + missing + " --case " + smooth, "missing.json"},
      {"montecarlo --case " + missing + " --method euler --trials 100 --seed 1", "missing.json"},
      {"nees --imu " + missing + " --ground-truth " + missing + " --noise " + missing +
           " --windows 1 --method rk4",
       "missing.json"},
      {"experiment both --trials 0", "--trials"},
  };
  for (const auto& [args, names] : cases) {
    const CommandResult r = RunImuconv(args, tmp);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, names)) << args << "\n" << r.err;
    EXPECT_FALSE(Has(r.err, "internal error")) << args << "\n" << r.err;
  }
  // Nothing was written by any of them (the one input file the test wrote only).
  EXPECT_EQ(tmp.entries(), 1u);
}

TEST(ExitCodes, AMissingBenchProgramIsAnInternalError) {
  // imuconv bench runs imuconv-bench beside the imuconv it is: a copy of imuconv alone in a
  // directory is an incomplete installation, not a bad input.
  const TempDir tmp;
  const std::string copy = tmp.file("imuconv");
  std::filesystem::copy_file(Binary(), copy);
  const std::string cmd = ShellQuote(copy) + " bench > " + ShellQuote(tmp.file("out")) + " 2> " +
                          ShellQuote(tmp.file("err"));
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3) << ReadText(tmp.file("err"));
  EXPECT_TRUE(Has(ReadText(tmp.file("err")), "imuconv-bench")) << ReadText(tmp.file("err"));
}

/// imuconv `args` is refused as bad input (exit 2) with a message holding `says`; the result,
/// for what else a test asserts of it.
CommandResult ExpectRefusedSaying(const std::string& args, const std::string& says,
                                  const TempDir& tmp) {
  CommandResult r = RunImuconv(args, tmp);
  EXPECT_EQ(r.exit_code, 2) << args;
  EXPECT_TRUE(Has(r.err, says)) << r.err;
  return r;
}

TEST(DidYouMean, ASubcommandTypoNamesTheNearest) {
  const TempDir tmp;
  // CLI11 alone said only "A subcommand is required".
  ExpectRefusedSaying(
      "chek a.json --case b.json",
      "unknown subcommand 'chek' (did you mean 'check'?); the subcommands are: ", tmp);
  ExpectRefusedSaying("-q montecarol --case x.json",
                      "unknown subcommand 'montecarol' (did you mean 'montecarlo'?)", tmp);
  // Nothing close: the list, no guess.
  ExpectRefusedSaying("frobnicate",
                      "unknown subcommand 'frobnicate'; the subcommands are: plugins, ", tmp);
  // The values of a main option are not taken for the subcommand.
  const CommandResult r = RunImuconv("--plugin-dir " + ShellQuote(tmp.path()) + " chek", tmp);
  EXPECT_TRUE(Has(r.err, "unknown subcommand 'chek' (did you mean 'check'?)")) << r.err;
  ExpectRefusedSaying("--quite run p.json",
                      "unknown option '--quite' (did you mean '--quiet'?) before the subcommand",
                      tmp);
}

TEST(DidYouMean, AFlagTypoNamesTheNearestFlagOfThatSubcommand) {
  const TempDir tmp;
  const std::string smooth = ShellQuote(DataPath("reference/cases/smooth-0.json"));
  ExpectRefusedSaying(
      "montecarlo --case " + smooth + " --method euler --trails 100 --seed 1",
      "unknown option '--trails' for 'imuconv montecarlo' (did you mean '--trials'?)", tmp);
  ExpectRefusedSaying("nees --pipeline p.json --window 1 --method rk4",
                      "unknown option '--window' for 'imuconv nees' (did you mean '--windows'?)",
                      tmp);
  ExpectRefusedSaying("check m.json --case c.json --jsno", "(did you mean '--json'?)", tmp);
  // A hidden option is accepted but never suggested; a negative number is a value, not a flag.
  CommandResult r = ExpectRefusedSaying(
      "montecarlo --case " + smooth + " --method euler --trials 100 --seed 1 --noise-scal 2",
      "unknown option '--noise-scal' for 'imuconv montecarlo'", tmp);
  EXPECT_FALSE(Has(r.err, "did you mean '--noise-scale'")) << r.err;
  // Every flag known: the parser's own message (here a value out of range), no guess.
  r = RunImuconv("experiment both --trials -5", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(Has(r.err, "did you mean")) << r.err;
  EXPECT_TRUE(Has(r.err, "--trials")) << r.err;
}

TEST(DidYouMean, APluginIdTypoNamesTheNearestId) {
  const TempDir tmp;
  const std::string state = ShellQuote(SourcePath("examples/hover.state.json"));
  // On the command line (convert's own check of the id) ...
  ExpectRefusedSaying(
      "convert --what jacobian --from left --to gtsam_NavState --state " + state,
      "unknown state convention 'gtsam_NavState' (did you mean 'gtsam_navstate'?); known: ", tmp);
  // ... and in a pipeline (the pipeline's id checks, by JSON pointer): examples/inline_basics.json
  // with its first task's propagator mistyped.
  json p = ReadJson(SourcePath("examples/inline_basics.json"));
  ASSERT_EQ(p["tasks"][0]["propagator"], "rk4");
  p["tasks"][0]["propagator"] = "RK4";
  const CommandResult r = RunImuconv(
      "run " + ShellQuote(tmp.write("p.json", p.dump())) + " -o " + ShellQuote(tmp.file("o.json")),
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "/tasks/0/propagator") &&
              Has(r.err, "unknown propagator 'RK4' (did you mean 'rk4'?)"))
      << r.err;
}

}  // namespace
