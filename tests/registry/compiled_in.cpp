// Plugins compiled into the program instead of loaded from shared objects (plugin_abi.h,
// IMUCONV_PLUGIN_STATIC). This test executable compiles three of the built-in plugin sources
// that way (tests/CMakeLists.txt: left, gtsam_navstate, euler): the registry adopts them with
// the same checks as a file's, they take the built-in directory's place on the search path,
// and they compute exactly what the shared-object plugins compute (the same code: bitwise).
// A shared-object plugin still loads beside them at run time.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "../integrators/integrator_cases.h"
#include "imuconv/plugin_kind.h"
#include "imuconv/registry.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"

namespace {

using imuconv::PluginKind;
using imuconv::Registry;

/// The plugins a registry holds beyond the reference chart every registry has built in
/// (preint_reference, file "built-in").
std::size_t Loaded(const Registry& reg) {
  return std::count_if(reg.plugins().begin(), reg.plugins().end(),
                       [](const imuconv::PluginInfo& i) { return i.file != "built-in"; });
}

imuconv::ImuState SomeState() {
  imuconv::ImuState x;
  x.R = imuconv::so3::Exp(imuconv::Vec3(0.3, -0.7, 1.1));
  x.p = imuconv::Vec3(1, 2, 3);
  x.v = imuconv::Vec3(0.5, -0.2, 0.1);
  x.bg = imuconv::Vec3(1e-3, -2e-3, 5e-4);
  x.ba = imuconv::Vec3(0.02, -0.01, 0.03);
  return x;
}

TEST(CompiledIn, TheProgramsPluginsAreAdoptedWithTheirChecks) {
  ASSERT_TRUE(Registry::has_compiled_in());
  EXPECT_EQ(imuconv::detail::CompiledInPlugins().size(), 3u);
  Registry reg;
  reg.load_compiled_in();
  for (const auto& [kind, id] : {std::pair{PluginKind::StateConvention, "left"},
                                 std::pair{PluginKind::StateConvention, "gtsam_navstate"},
                                 std::pair{PluginKind::Propagator, "euler"}}) {
    ASSERT_TRUE(reg.has(kind, id)) << id;
    EXPECT_EQ(reg.info(kind, id).file, Registry::kCompiledIn);
  }
  // The conventions were checked on adoption (round trip, analytic Jacobians vs Ridders').
  EXPECT_TRUE(reg.info(PluginKind::StateConvention, "gtsam_navstate").analytic_jacobians);
  reg.load_compiled_in();  // a second call adopts nothing again
  EXPECT_EQ(Loaded(reg), 3u);
}

TEST(CompiledIn, TheyTakeTheBuiltInDirectorysPlaceAndComputeTheSame) {
  Registry compiled;
  const auto issues = compiled.load_search_path();
  EXPECT_TRUE(issues.empty());
  // Only the compiled-in three: the built-in directory's 24 shared objects are not scanned.
  EXPECT_EQ(Loaded(compiled), 3u);
  for (const auto& info : compiled.plugins()) {
    if (info.file != "built-in") {
      EXPECT_EQ(info.file, Registry::kCompiledIn) << info.id;
    }
  }

  Registry files;  // the same plugins from the build's shared objects
  for (const char* f : {"imuconv_plugin_state_left.so", "imuconv_plugin_state_gtsam_navstate.so",
                        "imuconv_plugin_integrators_euler.so"})
    files.load_file(Registry::default_plugin_dir() + "/" + f);
  const imuconv::ImuState x = SomeState();
  EXPECT_EQ(compiled.conversion("left", "gtsam_navstate", x),
            files.conversion("left", "gtsam_navstate", x));

  const imuconv::test::ImuCase c = imuconv::test::LoadCase("smooth-1");
  const imuconv::PropagationInput in =
      imuconv::test::MakeInput(c, c.samples.front().t, c.samples.back().t);
  const imuconv::PropagationResult a = compiled.propagate("euler", "gtsam_navstate", in);
  const imuconv::PropagationResult b = files.propagate("euler", "gtsam_navstate", in);
  EXPECT_EQ(a.x_e.p, b.x_e.p);
  EXPECT_EQ(a.x_e.R, b.x_e.R);
  EXPECT_EQ(a.Phi, b.Phi);
  EXPECT_EQ(a.cov, b.cov);
}

TEST(CompiledIn, SharedObjectPluginsStillLoadBesideThem) {
  Registry reg;
  reg.load_compiled_in();
  reg.load_file(Registry::default_plugin_dir() + "/imuconv_plugin_state_openvins_jpl.so");
  EXPECT_TRUE(reg.has(PluginKind::StateConvention, "openvins_jpl"));
  const imuconv::Mat15 J = reg.conversion("openvins_jpl", "left", SomeState());
  const imuconv::Mat15 back = reg.conversion("left", "openvins_jpl", SomeState());
  EXPECT_LE((J * back - imuconv::Mat15::Identity()).cwiseAbs().maxCoeff(),
            1e-12);  // a round trip, to rounding
  // A file that declares an id already compiled in is a duplicate, named as such.
  try {
    reg.load_file(Registry::default_plugin_dir() + "/imuconv_plugin_state_left.so");
    FAIL() << "a second 'left' was accepted";
  } catch (const imuconv::Error& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate state_convention plugin id 'left'"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("compiled-in"), std::string::npos) << e.what();
  }
}

}  // namespace
