// The `tangent` and `manifold` preintegrators against GTSAM's own numbers
// (tests/data/reference/gtsam, see FORMAT.md) on all ten reference cases:
//   zoh: the case's samples under a zero-order hold (what GTSAM was fed);
//   mid: the mean of consecutive samples held over each interval, fed here as an explicit
//        sample vector of means with the same timestamps.
// Fields: deltaT, deltaR, deltaP, deltaV, J_bias, cov15, and cov9 (the same scheme with
// zero bias random walk, top-left 9x9), and for tangent its 9-vector xi
// (preintegrated_tangent). Metric: the paper's entrywise difference d.
// The plugins run the kernel instance the CPU selects; every other compiled instance
// (baseline x86-64, AVX2, AVX-512, as the CPU allows) is held to the same bound.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "imuconv/kernels/gtsam_preintegration.h"
#include "imuconv_test.h"
#include "reference_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;

// GTSAM and these kernels evaluate the same recursions in a different operation order, so
// agreement is limited only by rounding accumulated over 1000-2000 steps (~1e-11 on
// well-conditioned entries); 1e-8 is the accuracy the project promises (FORMAT.md).
constexpr double kMaxD = 1e-8;

const char* const kFields[] = {"deltaT", "deltaR", "deltaP", "deltaV", "J_bias", "cov15", "cov9", "xi"};

struct SchemeReport {
  std::map<std::string, WorstDiff> worst;  // field -> worst over cases
};

void CompareCase(const Preintegrator& pre, const ReferenceCase& rc, const nlohmann::json& ref,
                 const std::string& label, SchemeReport& report) {
  SCOPED_TRACE(label);
  NativePreintegration out;
  const PreintegrationInput in = rc.Input();
  const Status st = pre.integrate(in, out);
  ASSERT_TRUE(st.ok()) << st.message();

  // cov9: PreintegratedImuMeasurements has no bias states, i.e. zero random walk.
  PreintegrationInput in9 = in;
  in9.noise.gyro_random_walk = in9.noise.accel_random_walk = 0.0;
  NativePreintegration out9;
  ASSERT_TRUE(pre.integrate(in9, out9).ok());

  Eigen::Matrix<double, 1, 1> dT_ref, dT_est;
  dT_ref(0) = ref.at("deltaT").get<double>();
  dT_est(0) = out.dt;
  const std::pair<Eigen::MatrixXd, Eigen::MatrixXd> fields[] = {
      {dT_ref, dT_est},
      {JsonMatrix(ref.at("deltaR")), out.delta.dR},
      {JsonMatrix(ref.at("deltaP")), out.delta.dp},
      {JsonMatrix(ref.at("deltaV")), out.delta.dv},
      {JsonMatrix(ref.at("J_bias")), out.J_bias},
      {JsonMatrix(ref.at("cov15")), out.cov},
      {JsonMatrix(ref.at("cov9")), out9.cov.topLeftCorner<9, 9>()},
  };
  double case_worst = 0.0;
  std::string case_field;
  for (int f = 0; f < 7; ++f) {
    const auto& [r, e] = fields[f];
    ASSERT_EQ(r.rows(), e.rows()) << kFields[f];
    ASSERT_EQ(r.cols(), e.cols()) << kFields[f];
    int i = 0, k = 0;
    const double d = MaxEntryDiffAt(r, e, i, k);
    char where[160];
    std::snprintf(where, sizeof where, "%s (%d,%d) ref %.17g est %.17g", rc.id.c_str(), i, k, r(i, k), e(i, k));
    report.worst[kFields[f]].Update(d, where);
    EXPECT_LE(d, kMaxD) << kFields[f] << " at " << where;
    if (d > case_worst) case_worst = d, case_field = kFields[f];
  }
  std::printf("    %-12s max d %.2e (%s)\n", rc.id.c_str(), case_worst, case_field.c_str());

  // Tangent only: GTSAM's own 9-vector [theta, p, v] (the scheme's state; theta is never
  // wrapped, so it is compared directly rather than through Log(dR)), from the kernel the
  // plugin runs.
  if (ref.contains("preintegrated_tangent")) {
    kernels::TangentIncrement inc;
    NativePreintegration o;
    ASSERT_TRUE(kernels::IntegrateTangent<false>(in, o, &inc).ok());
    const Eigen::MatrixXd r = JsonMatrix(ref.at("preintegrated_tangent"));
    int i = 0, k = 0;
    const double d = MaxEntryDiffAt(r, Eigen::MatrixXd(inc.xi), i, k);
    char where[160];
    std::snprintf(where, sizeof where, "%s (%d) ref %.17g est %.17g", rc.id.c_str(), i, r(i, k), inc.xi(i));
    report.worst["xi"].Update(d, where);
    EXPECT_LE(d, kMaxD) << "preintegrated_tangent at " << where;
  }
}

/// The kernels of one scheme, one compiled instance, behind the plugin interface.
class KernelInstance final : public Preintegrator {
 public:
  KernelInstance(std::string scheme, kernels::Isa isa) : scheme_(std::move(scheme)), isa_(isa) {}
  const char* id() const noexcept override { return scheme_.c_str(); }
  const char* cov_convention() const noexcept override { return ""; }
  const char* jacobian_convention() const noexcept override { return ""; }
  Status integrate(const PreintegrationInput& in, NativePreintegration& out) const noexcept override {
    return scheme_ == "manifold" ? kernels::IntegrateManifold(in, out, nullptr, isa_)
                                 : kernels::IntegrateTangent(in, out, nullptr, isa_);
  }

 private:
  std::string scheme_;
  kernels::Isa isa_;
};

void RunScheme(const std::string& scheme, const std::string& slot, kernels::Isa isa = kernels::Isa::kAuto) {
  const char* isa_name = isa == kernels::Isa::kBaseline ? " (baseline instance)"
                         : isa == kernels::Isa::kAvx2   ? " (AVX2 instance)"
                         : isa == kernels::Isa::kAvx512 ? " (AVX-512 instance)"
                                                        : "";
  if (!kernels::IsaAvailable(isa)) {
    std::printf("[ skipped ] %s%s: not supported by this CPU\n", scheme.c_str(), isa_name);
    return;
  }
  const KernelInstance instance(scheme, isa);
  const auto plugin = isa == kernels::Isa::kAuto ? Plugins().preintegrator(scheme) : nullptr;
  const Preintegrator& pre = plugin ? *plugin : instance;
  SchemeReport report;
  std::printf("[ per case ] %s %s%s, worst d over all fields:\n", scheme.c_str(), slot.c_str(), isa_name);
  for (const std::string& id : ReferenceCaseIds()) {
    const ReferenceCase zoh = LoadReferenceCase(id);
    const ReferenceCase rc = slot == "mid" ? zoh.Averaged() : zoh;
    const nlohmann::json ref = LoadGtsamReference(id).at(slot).at(scheme);
    CompareCase(pre, rc, ref, id + " " + slot + " " + scheme, report);
  }
  std::printf("[ worst d ] %s %s%s over %zu cases:\n", scheme.c_str(), slot.c_str(), isa_name,
              ReferenceCaseIds().size());
  for (const char* f : kFields) {
    if (!report.worst.count(f)) continue;
    const WorstDiff& w = report.worst[f];
    std::printf("    %-7s %.3e  at %s\n", f, w.d, w.where.c_str());
  }
}

TEST(GtsamReference, TangentZeroOrderHold) { RunScheme("tangent", "zoh"); }
TEST(GtsamReference, ManifoldZeroOrderHold) { RunScheme("manifold", "zoh"); }
TEST(GtsamReference, TangentMidpointSamples) { RunScheme("tangent", "mid"); }
TEST(GtsamReference, ManifoldMidpointSamples) { RunScheme("manifold", "mid"); }
TEST(GtsamReference, EveryKernelInstance) {
  for (kernels::Isa isa : {kernels::Isa::kBaseline, kernels::Isa::kAvx2, kernels::Isa::kAvx512})
    for (const char* scheme : {"tangent", "manifold"}) RunScheme(scheme, "zoh", isa);
}

}  // namespace
