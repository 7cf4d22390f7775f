// The preintegrators' mean-only path (increment_mean()): each plugin's declaration, made in its
// system's own test file (IMUCONV_INCREMENT_MEAN), checked as tests/support/
// increment_mean_facts.h says (bit for bit against the full path where it is provided; "not
// provided" and the identity where it is not); every preintegrator loaded from the built-in
// plugin directory must have one. tests/integrators/mean_only.cpp does the same for the
// propagators and says why bit for bit is the bound.
#include <gtest/gtest.h>

#include "increment_mean_facts.h"

namespace {

TEST(MeanOnly, EveryBuiltInPreintegratorGivesWhatItDeclares) {
  imuconv::test::CheckDeclaredIncrementMeans<imuconv::PluginKind::Preintegrator>(
      "the preintegrator's own test file in tests/preintegrators/");
}

}  // namespace
