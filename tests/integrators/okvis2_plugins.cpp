// The `okvis2` propagators as a window feeds them (kernels/okvis2_scheme.h): an interval whose
// ends fall between samples reaches OKVIS's loop as interpolated knots, which must be what
// OKVIS itself does with the raw samples and t_start, t_end inside a step (it interpolates the
// straddling samples linearly); a time OKVIS cannot stamp is refused with a message, never
// computed with.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/kernels/okvis2.h"
#include "imuconv/kernels/okvis2_scheme.h"
#include "integrator_cases.h"
#include "scale_aware.h"
#include "scheme_fact_declarations.h"

namespace {

// What the two propagators say of their noise and mean (scheme_fact_declarations.h;
// docs/montecarlo.md): OKVIS's trapezoidal loop averages a step's two ends (centered cells);
// sigma_*_c are densities. Neither gives the mean alone (docs/okvis2.md): the trials run the
// full propagation.
IMUCONV_SCHEME_FACTS(Propagator, okvis2, kCentered, kContinuous, true, kNotProvided);
IMUCONV_SCHEME_FACTS(Propagator, okvis2_step_local, kCentered, kContinuous, true, kNotProvided);

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;

TEST(Okvis2Plugins, InterpolatedEndsAreOkvisOwnInterpolation) {
  const ImuCase c = LoadCase("jitter-1");
  // 2 s starting 0.4 of the way into a step of the jittered case, on whole nanoseconds so
  // that the window's knot and okvis::Time name the same instant.
  const double t_s =
      std::round((c.samples[30].t + 0.4 * (c.samples[31].t - c.samples[30].t)) * 1e9) / 1e9;
  const double t_e = t_s + 2.0;
  PropagationInput in = MakeInput(c, t_s, t_e);
  in.cov_s.setZero();
  for (const char* id : {"okvis2", "okvis2_step_local"}) {
    SCOPED_TRACE(id);
    const PropagationResult r = Plugins().propagate(id, "okvis2", in);

    // OKVIS on the raw samples, t_start and t_end inside a step.
    std::vector<Okvis2Sample> raw;
    for (const ImuSample& s : c.samples) {
      Okvis2Sample o;
      ASSERT_TRUE(Okvis2TimeFromSeconds(s.t, o.t_ns).ok());
      o.gyro = s.gyro;
      o.accel = s.accel;
      raw.push_back(o);
    }
    std::int64_t t0 = 0, t1 = 0;
    ASSERT_TRUE(Okvis2TimeFromSeconds(t_s, t0).ok());
    ASSERT_TRUE(Okvis2TimeFromSeconds(t_e, t1).ok());
    Okvis2ImuParameters params = Okvis2ParametersOf(c.noise);
    params.g = -c.gravity.z();
    Okvis2Propagation okvis;
    ASSERT_TRUE(PropagateOkvis2(raw, params, Okvis2StateOf(c.x_s), t0, t1, okvis,
                                std::string(id) == "okvis2" ? Okvis2Transition::kAsOkvis
                                                            : Okvis2Transition::kOkvisStepLocal)
                    .ok());
    // The two interpolations differ only in how the fraction of the step is formed: the
    // window's from seconds near 600 s in double (resolution 1.1e-13 s, so about 2.7e-11 of a
    // 5 ms step), OKVIS's from exact nanosecond counts. That moves the two interpolated
    // knots by 2.7e-11 of a sample difference, and the end state, covariance and Jacobian by
    // about as much relative (measured up to 3.6e-11, Phi); the rest is the same arithmetic.
    // Bound 1e-10 by the note's metric, relative above the floor for Phi and on the
    // correlation scale for the covariance: a knot fed at the wrong time (a whole step's
    // fraction, 0.4) or not interpolated gives 1e-3 and more.
    const double d_p = MaxEntryDiff(okvis.end.r, r.x_e.p);
    const double d_R = MaxEntryDiff(Mat3(okvis.end.q.toRotationMatrix()), r.x_e.R);
    const double d_v = MaxEntryDiff(okvis.end.v, r.x_e.v);
    const double d_cov = CorrelationScaleDiff(okvis.covariance, r.cov).d;
    const double d_Phi = RelativeAboveFloorDiff(okvis.jacobian, r.Phi).d;
    std::printf("  %-18s p %.2g R %.2g v %.2g cov %.2g Phi %.2g\n", id, d_p, d_R, d_v, d_cov,
                d_Phi);
    for (const double d : {d_p, d_R, d_v, d_cov, d_Phi}) EXPECT_LE(d, 1e-10);
    EXPECT_EQ(okvis.steps, static_cast<int>(in.window.size()) - 1);
  }
}

TEST(Okvis2Plugins, TimesOkvisCannotStampAreRefused) {
  // okvis::Time holds unsigned 32-bit seconds: a sample before 0 s has no stamp.
  ImuCase c = LoadCase("smooth-0");
  const double shift = c.samples.front().t + 1.0;
  for (ImuSample& s : c.samples) s.t -= shift;
  const PropagationInput in = MakeInput(c, c.samples.front().t, c.samples.front().t + 2.0);
  for (const char* id : {"okvis2", "okvis2_step_local"}) {
    try {
      (void)Plugins().propagate(id, "okvis2", in);
      ADD_FAILURE() << id << " propagated from a time before 0 s";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("OKVIS"), std::string::npos) << what;
      EXPECT_NE(what.find("knot 0"), std::string::npos) << what;
    }
  }
  try {
    (void)PreintegrateNative(Plugins(), "okvis2", in.window, c.x_s.bg, c.x_s.ba, c.noise);
    ADD_FAILURE() << "the okvis2 preintegrator integrated from a time before 0 s";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("OKVIS"), std::string::npos) << e.what();
  }
}

}  // namespace
