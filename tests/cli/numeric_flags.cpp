// Numbers on the command line that are not finite (issue 22): "nan", "inf", "1e999" and their
// kin are refused in every numeric option of every command, by one rule registered once for the
// whole command tree (cli_common.cpp, RefuseNonFiniteNumbers). Before, CLI11 read them as
// doubles and the range validators let NaN through (each comparison with it is false):
// --duration nan meant the whole case, --check-timeout nan became a deadline (undefined
// behaviour), --stride nan and --noise-scale 1e999 ran. Each is exit 2 naming the option, before
// any work, and nothing is written.
#include <gtest/gtest.h>

#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;

/// `args` with `flag value` appended must be refused: exit 2, the option and the rule named.
void ExpectFlagRefused(const std::string& args, const std::string& flag, const std::string& value,
                       const TempDir& tmp) {
  SCOPED_TRACE(flag + " " + value);
  const CommandResult r = RunImuconv(args + " " + flag + " " + ShellQuote(value), tmp);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_TRUE(Has(r.err, flag)) << r.err;
  // A list option is checked element by element: the message shows the element at fault.
  const std::string element =
      value.substr(value.rfind(',') == std::string::npos ? 0 : value.rfind(',') + 1);
  EXPECT_TRUE(Has(r.err, "expected a finite number, found '" + element + "'")) << r.err;
  EXPECT_EQ(r.out, "");
}

TEST(NumericFlags, NonFiniteValuesAreRefusedInEveryCommand) {
  TempDir tmp;
  const std::string montecarlo = "montecarlo --case " +
                                 ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                                 " --method rk4 --trials 16";
  ExpectFlagRefused(montecarlo, "--duration", "nan", tmp);
  ExpectFlagRefused(montecarlo, "--duration", "NaN", tmp);
  ExpectFlagRefused(montecarlo, "--noise-scale", "1e999", tmp);  // beyond the largest double: inf
  ExpectFlagRefused(montecarlo, "--duration", "0x1p99999", tmp);
  const std::string nees =
      "nees --imu " + ShellQuote(SourcePath("examples/data/V1_01_easy_imu0_slice.csv")) +
      " --ground-truth " +
      ShellQuote(SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv")) +
      " --noise " + ShellQuote(DataPath("kalibr/euroc_imu.yaml")) + " --method rk4";
  ExpectFlagRefused(nees + " --windows 0.5", "--stride", "nan", tmp);
  ExpectFlagRefused(nees, "--windows", "0.5,nan", tmp);
  ExpectFlagRefused("plugins --check " + ShellQuote(tmp.path()), "--check-timeout", "nan", tmp);
  ExpectFlagRefused("plugins --check " + ShellQuote(tmp.path()), "--check-timeout", "inf", tmp);
  ExpectFlagRefused("experiment preint-by-prop --trials 1", "--duration", "Infinity", tmp);
  ExpectFlagRefused("experiment preint-by-prop --trials 1", "--rate", "nan", tmp);
}

TEST(NumericFlags, IntegerOptionsRefuseInfinityToo) {
  // An integer option never took "inf" (CLI11 cannot convert it); the message is still exit 2
  // naming the option.
  TempDir tmp;
  const CommandResult r =
      RunImuconv("montecarlo --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                     " --method rk4 --trials inf",
                 tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "--trials")) << r.err;
}

TEST(NumericFlags, FiniteValuesAndNamesThatAreNotNumbersStillPass) {
  // The rule is about numbers only: a file named "nan" is still a file (given as ./nan), and a
  // finite value passes (the case is refused for another reason: it does not exist).
  TempDir tmp;
  const CommandResult r =
      RunImuconv("montecarlo --case ./nan --method rk4 --trials 16 --seed 1 --duration 0.5", tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(Has(r.err, "finite")) << r.err;
  EXPECT_TRUE(Has(r.err, "nan")) << r.err;
}

}  // namespace
