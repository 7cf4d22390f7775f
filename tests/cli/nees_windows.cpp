// imuconv nees: which windows are fitted. The number of windows is bounded over all the
// lengths together, refused before any is propagated.
//
// Every run here is refused before propagating: well under a second.
#include <gtest/gtest.h>

#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

std::string SliceArgsRk4(const TempDir& tmp) {
  return "--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
         ShellQuote(kEurocSliceGroundTruth) + " --noise " +
         ShellQuote(tmp.write("noise.json", kEurocNoise.dump())) + " --method rk4";
}

// Three lengths of a stride typo (2.05e-5 s on 20 s of data): some 980 000 windows each, under
// the bound one at a time, three times it together. Refused at once, naming both options.
TEST(NeesWindows, TooManyWindowsOverAllLengthsAreRefused) {
  const TempDir tmp;
  const CommandResult r = RunImuconv(
      "nees " + SliceArgsRk4(tmp) + " --windows 0.01,0.011,0.012 --stride 0.0000205", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--windows, --stride: 3 window length(s) at a stride of 2.05e-05 s") &&
              Has(r.err, "more than 1000000 in all"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
