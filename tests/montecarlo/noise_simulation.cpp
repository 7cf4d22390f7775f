// What the built-in plugins say of their noise (noise_simulation(), core/include/imuconv/
// noise_simulation.h), which imuconv montecarlo simulates without naming any method: the cells
// and readings of docs/montecarlo.md's lists and table, which montecarlo kept by id until the
// plugins carried them. The cells follow from each scheme's arithmetic (docs/noise.md): a held
// sample's cell is the step it is held over, a scheme averaging a step's two ends or
// interpolating between knots weighs each sample over half of each step beside it.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "imuconv_test.h"
#include "montecarlo.h"

namespace imuconv::montecarlo {
namespace {

using test::Plugins;

NoiseSimulation Of(PluginKind kind, const char* id) {
  return kind == PluginKind::Propagator ? Plugins().propagator(id)->noise_simulation()
                                        : Plugins().preintegrator(id)->noise_simulation();
}

TEST(MontecarloNoiseSimulation, TheBuiltInPluginsSayTheirCellsAndReadings) {
  constexpr PluginKind P = PluginKind::Propagator, N = PluginKind::Preintegrator;
  const struct {
    PluginKind kind;
    const char* id;
    SampleCells cells;
    NoiseReading reading;
    bool simulable;
  } kExpected[] = {
      {P, "euler", SampleCells::kForward, NoiseReading::kContinuous, true},
      {P, "midpoint", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {P, "rk4", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {P, "openvins_discrete", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {P, "openvins_analytical", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {P, "openvins_rk4", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {N, "manifold", SampleCells::kForward, NoiseReading::kContinuous, true},
      {N, "tangent", SampleCells::kForward, NoiseReading::kContinuous, true},
      {N, "vins_fusion", SampleCells::kCentered, NoiseReading::kContinuous, true},
      {N, "vins_fusion_as_configured", SampleCells::kCentered, NoiseReading::kContinuous, false},
      {N, "basalt", SampleCells::kBackward, NoiseReading::kWalkInIncrementOnly, true},
      {N, "basalt_forward_zoh", SampleCells::kForward, NoiseReading::kWalkInIncrementOnly, true},
      {N, "basalt_as_configured", SampleCells::kBackward, NoiseReading::kPerSampleStd, true},
  };
  for (const auto& e : kExpected) {
    const NoiseSimulation sim = Of(e.kind, e.id);
    EXPECT_EQ(sim.cells, e.cells) << e.id;
    EXPECT_EQ(sim.reading, e.reading) << e.id;
    EXPECT_EQ(sim.simulable, e.simulable) << e.id;
    ASSERT_NE(sim.note, nullptr) << e.id;
  }
}

// montecarlo's model follows the plugin: the reading's name in the output, the mismatch flag,
// and the plugin's note (which says where its reading is documented).
TEST(MontecarloNoiseSimulation, TheModelIsThePluginsReading) {
  const auto model = [](PluginKind kind, const char* id) {
    return NoiseModelFor(ResolvePreintegrationMethod(Plugins(), kind, id));
  };
  const NoiseModel basalt = model(PluginKind::Preintegrator, "basalt");
  EXPECT_EQ(basalt.simulated, "basalt");
  EXPECT_TRUE(basalt.matches);
  EXPECT_NE(basalt.note.find("docs/basalt.md"), std::string::npos) << basalt.note;
  const NoiseModel per_sample = model(PluginKind::Preintegrator, "basalt_as_configured");
  EXPECT_EQ(per_sample.simulated, "basalt_per_sample");
  const NoiseModel vins = model(PluginKind::Preintegrator, "vins_fusion_as_configured");
  EXPECT_EQ(vins.simulated, "continuous");
  EXPECT_FALSE(vins.matches);
  EXPECT_NE(vins.note.find("MISMATCH"), std::string::npos) << vins.note;
  const NoiseModel rk4 = model(PluginKind::Propagator, "rk4");
  EXPECT_EQ(rk4.simulated, "continuous");
  EXPECT_TRUE(rk4.matches);
}

// Values outside the enums (a plugin built against another header) are hostile input: simulated
// as the defaults, and said as a mismatch rather than taken silently.
TEST(MontecarloNoiseSimulation, AnUnknownCellOrReadingIsSaidAsAMismatch) {
  struct Bogus final : Propagator {
    const char* id() const noexcept override { return "bogus"; }
    const char* native_convention() const noexcept override { return "left"; }
    Status propagate(const PropagationInput&, PropagationResult&) const noexcept override {
      return Status::Ok();
    }
    NoiseSimulation noise_simulation() const noexcept override {
      NoiseSimulation sim;
      sim.cells = static_cast<SampleCells>(7);
      sim.note = nullptr;  // also hostile: no note at all
      return sim;
    }
  };
  PreintegrationMethod method;
  method.id = "bogus";
  method.kind = PluginKind::Propagator;
  method.propagator = std::make_shared<Bogus>();
  const NoiseModel m = NoiseModelFor(method);
  EXPECT_EQ(m.simulated, "continuous");
  EXPECT_FALSE(m.matches);
  EXPECT_NE(m.note.find("cells 7"), std::string::npos) << m.note;
}

}  // namespace
}  // namespace imuconv::montecarlo
