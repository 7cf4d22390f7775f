// OpenVINS's own numbers (tests/data/reference/anchors/openvins, README.md there) for its two
// other integration methods: IntegrationMethod::RK4 and IntegrationMethod::ANALYTICAL over
// each of the ten reference cases, against imuconv's `openvins_rk4` and `openvins_analytical`
// propagators expressed in OpenVINS's error state (`openvins_jpl`), through
// Registry::propagate. The same comparison as openvins_anchor.cpp makes for DISCRETE.
//
// Tolerances: the anchors' bounds (anchors.h), 1e-8 by the metric of J. Huai, "IMU
// Propagation as Preintegration", and 1e-9 scale-aware, for the reason given there: the same
// scheme computed in another order (here with the step's transition formed in the `left`
// chart and converted) differs by rounding only, accumulated over 2000 steps.
// Measured (GCC 12, x86-64), worst over the ten cases, by the metric:
//   rk4         state 5.3e-12 (rotation, smooth-0), Phi 1.6e-10 (smooth-3), covariance 3.5e-11,
//               Qd 4.9e-12; scaled Phi 6.0e-11, covariance 7.4e-13, Qd 9.5e-13;
//   analytical  state 5.0e-12 (rotation, smooth-0), Phi 1.8e-10 (white-0), covariance 3.5e-11,
//               Qd 5.9e-12; scaled Phi 6.6e-11, covariance 1.3e-12, Qd 7.3e-13.
// The two methods differ from each other by up to 1.5e-3 rad and 0.3 m in the state
// (openvins_methods.cpp), so a method confused with the other is caught by orders of magnitude.
// No reference case turns slower than pi/360 rad/s, so upstream's small-rate forms of the Xi
// integrals are not exercised by these numbers.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <tuple>

#include "anchors.h"
#include "imuconv/registry.h"
#include "imuconv_test.h"
#include "scale_aware.h"

namespace {

using imuconv::Mat15;
using imuconv::PropagationInput;
using imuconv::PropagationResult;
using namespace imuconv::test;  // DataPath, JsonMatrix, MaxEntryDiff, Plugins, the anchors' bounds

struct Method {
  const char* plugin;  // imuconv's propagator id
  const char* key;     // the anchor files' method key
};
const Method kMethods[] = {{"openvins_rk4", "rk4"}, {"openvins_analytical", "analytical"}};

class OpenVinsMethodAnchor : public ::testing::TestWithParam<std::tuple<Method, const char*>> {};

TEST_P(OpenVinsMethodAnchor, PropagationIsOpenVinsOwn) {
  const Method method = std::get<0>(GetParam());
  const std::string id = std::get<1>(GetParam());
  const nlohmann::json anchor = ReadJson(DataPath("reference/anchors/openvins/" + id + ".json"));
  const nlohmann::json& in_json = anchor.at("inputs");
  const nlohmann::json& ov = anchor.at(method.key);
  const ImuCase c = LoadCase(id);

  // OpenVINS propagates from its first sample to its last with the case's densities and
  // gravity magnitude; P0 is the case's start covariance in its error state.
  ASSERT_EQ(in_json.at("n_imu").get<std::size_t>(), c.samples.size());
  ASSERT_EQ(in_json.at("sigma_w").get<double>(), c.noise.gyro_noise_density);
  ASSERT_EQ(in_json.at("sigma_a").get<double>(), c.noise.accel_noise_density);
  ASSERT_EQ(in_json.at("sigma_wb").get<double>(), c.noise.gyro_random_walk);
  ASSERT_EQ(in_json.at("sigma_ab").get<double>(), c.noise.accel_random_walk);
  ASSERT_EQ(-in_json.at("gravity_mag").get<double>(), c.gravity.z());
  PropagationInput in = MakeInput(c, in_json.at("t_start").get<double>(), in_json.at("t_end").get<double>());
  in.cov_s = JsonMatrix(in_json.at("P0"));
  const PropagationResult r = Plugins().propagate(method.plugin, "openvins_jpl", in);
  // Qd_summed is the noise alone: the same propagation from a zero covariance.
  in.cov_s.setZero();
  const PropagationResult q = Plugins().propagate(method.plugin, "openvins_jpl", in);

  const nlohmann::json& end = ov.at("state_end");
  const double d_p = MaxEntryDiff(JsonMatrix(end.at("p_IinG")), r.x_e.p);
  const double d_v = MaxEntryDiff(JsonMatrix(end.at("v_IinG")), r.x_e.v);
  const double d_R = MaxEntryDiff(JsonMatrix(end.at("R_GtoI")), r.x_e.R.transpose());
  const double d_b =
      std::max(MaxEntryDiff(JsonMatrix(end.at("bg")), r.x_e.bg), MaxEntryDiff(JsonMatrix(end.at("ba")), r.x_e.ba));
  const Mat15 cov = JsonMatrix(ov.at("covariance")), Phi = JsonMatrix(ov.at("Phi_summed")),
              Qd = JsonMatrix(ov.at("Qd_summed"));
  const double d_cov = MaxEntryDiff(cov, r.cov), d_Phi = MaxEntryDiff(Phi, r.Phi), d_Qd = MaxEntryDiff(Qd, q.cov);
  const auto s_cov = CorrelationScaleDiff(cov, r.cov), s_Qd = CorrelationScaleDiff(Qd, q.cov);
  const auto s_Phi = RelativeAboveFloorDiff(Phi, r.Phi);
  std::printf("  %-10s %-13s p %.2g v %.2g R %.2g b %.2g | cov %.2g Phi %.2g Qd %.2g | scaled cov %.2g Phi %.2g "
              "Qd %.2g\n",
              method.key, id.c_str(), d_p, d_v, d_R, d_b, d_cov, d_Phi, d_Qd, s_cov.d, s_Phi.d, s_Qd.d);
  for (const double d : {d_p, d_v, d_R, d_b, d_cov, d_Phi, d_Qd}) EXPECT_LE(d, kAnchorMetricTol);
  EXPECT_LE(s_cov.d, kAnchorScaledTol) << "covariance at (" << s_cov.row << "," << s_cov.col << ")";
  EXPECT_LE(s_Qd.d, kAnchorScaledTol) << "Qd at (" << s_Qd.row << "," << s_Qd.col << ")";
  EXPECT_LE(s_Phi.d, kAnchorScaledTol) << "Phi at (" << s_Phi.row << "," << s_Phi.col << ")";
  EXPECT_NEAR(ov.at("dt_summed").get<double>(), c.samples.back().t - c.samples.front().t, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Reference, OpenVinsMethodAnchor,
                         ::testing::Combine(::testing::ValuesIn(kMethods), ::testing::ValuesIn(kReferenceCaseIds)),
                         [](const ::testing::TestParamInfo<OpenVinsMethodAnchor::ParamType>& info) {
                           std::string name = std::string(std::get<0>(info.param).key) + "_" + std::get<1>(info.param);
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

}  // namespace
