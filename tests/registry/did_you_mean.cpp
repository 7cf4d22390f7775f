// Did-you-mean (registry/include/imuconv/did_you_mean.h): the edit distance on hand-counted
// pairs, the suggestion rule, and the registry's unknown-id error carrying it (so the pipeline,
// the command line and the Python module all get it).
#include <gtest/gtest.h>

#include <string>

#include "imuconv/did_you_mean.h"
#include "imuconv/registry.h"

namespace {
using namespace imuconv;

TEST(DidYouMean, EditDistanceCountsEachSlipOnce) {
  // Each pair counted by hand: the operations that turn one into the other.
  EXPECT_EQ(EditDistance("check", "check"), 0u);
  EXPECT_EQ(EditDistance("chek", "check"), 1u);                     // one insertion
  EXPECT_EQ(EditDistance("--trails", "--trials"), 1u);              // one transposition (a, i)
  EXPECT_EQ(EditDistance("gtsam_NavState", "gtsam_navstate"), 0u);  // case only
  EXPECT_EQ(EditDistance("rk5", "rk4"), 1u);                        // one substitution
  EXPECT_EQ(EditDistance("", "abc"), 3u);                           // three insertions
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);                 // k->s, e->i, +g
  EXPECT_EQ(EditDistance("montecarol", "montecarlo"), 1u);          // one transposition (o, l)
  EXPECT_EQ(EditDistance("abc", "ca"),
            3u);  // optimal string alignment: no edit of a transposed pair
  // Symmetric.
  EXPECT_EQ(EditDistance("convertt", "conversion"), EditDistance("conversion", "convertt"));
}

TEST(DidYouMean, HostileLengthsAreBounded) {
  // Beyond 256 characters nothing is compared (O(n m) work on hostile text): the distance is
  // then at least 256, so no suggestion is made.
  const std::string huge(100000, 'a');
  EXPECT_GE(EditDistance(huge, "a"), 256u);
  EXPECT_TRUE(ClosestNames(huge, {std::string(100000, 'a') + "b"}).empty());
}

TEST(DidYouMean, SuggestsOnlyTheNearestWithinTheAllowance) {
  const std::vector<std::string> subcommands{"plugins",    "conversion", "convert",   "run",
                                             "merge",      "refcase",    "bench",     "check",
                                             "montecarlo", "nees",       "experiment"};
  EXPECT_EQ(ClosestNames("chek", subcommands), std::vector<std::string>{"check"});
  EXPECT_EQ(ClosestNames("conver", subcommands),
            std::vector<std::string>{"convert"});  // 1 from convert, 4 from conversion
  EXPECT_EQ(ClosestNames("nes", subcommands), std::vector<std::string>{"nees"});
  EXPECT_TRUE(ClosestNames("check", subcommands).empty());  // known: nothing to suggest
  EXPECT_TRUE(ClosestNames("xyzzy", subcommands).empty());  // nothing close
  // A short word is allowed one slip (max(1, 3/4) = 1): "rnu" (a transposition) is suggested
  // "run", "rnx" (two slips) nothing.
  EXPECT_EQ(ClosestNames("rnu", {"run"}), std::vector<std::string>{"run"});
  EXPECT_TRUE(ClosestNames("rnx", {"run"}).empty());
  // A long one two (max(1, 9/4) = 2): "exprimnet" (a deletion and a transposition) is
  // suggested "experiment"; "exprimnetx", three slips, is not.
  EXPECT_EQ(EditDistance("exprimnet", "experiment"), 2u);
  EXPECT_EQ(ClosestNames("exprimnet", {"experiment"}), std::vector<std::string>{"experiment"});
  EXPECT_EQ(EditDistance("exprimnetx", "experiment"), 3u);
  EXPECT_TRUE(ClosestNames("exprimnetx", {"experiment"}).empty());
  // Never more than three slips, however long the word: a 24-character id with four is not
  // "meant" for the known one.
  EXPECT_EQ(EditDistance("right_invariant_se23xxxx", "right_invariant_se23"), 4u);
  EXPECT_TRUE(ClosestNames("right_invariant_se23xxxx", {"right_invariant_se23"}).empty());
  EXPECT_EQ(ClosestNames("right_invariant_se23xxx", {"right_invariant_se23"}),
            std::vector<std::string>{"right_invariant_se23"});
  // Ties are all named, in the order given.
  EXPECT_EQ(ClosestNames("rk", {"rk4", "rk2", "euler"}), (std::vector<std::string>{"rk4", "rk2"}));
  EXPECT_EQ(DidYouMean("rk", {"rk4", "rk2", "euler"}), " (did you mean 'rk4' or 'rk2'?)");
  EXPECT_EQ(DidYouMean("chek", subcommands), " (did you mean 'check'?)");
  EXPECT_EQ(DidYouMean("xyzzy", subcommands), "");
  // Names are quoted with Printable's escaping: a control character in a plugin id stays visible.
  EXPECT_EQ(DidYouMean("a\x01", {"a\x01"
                                 "b"}),
            " (did you mean 'a\\x01b'?)");
}

TEST(DidYouMean, TheRegistryNamesTheNearestPluginId) {
  Registry reg;
  ASSERT_TRUE(
      reg.load_directory(Registry::default_plugin_dir()).empty());  // every built-in plugin loads
  ASSERT_TRUE(reg.has(PluginKind::StateConvention, "gtsam_navstate"));
  try {
    reg.state_convention("gtsam_NavState");
    FAIL() << "an unknown id must throw";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'gtsam_NavState' is loaded (did you mean 'gtsam_navstate'?); known: "),
              std::string::npos)
        << m;
  }
  try {
    reg.info(PluginKind::Propagator, "RK4");
    FAIL() << "an unknown id must throw";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("(did you mean 'rk4'?)"), std::string::npos) << m;
  }
}

}  // namespace
