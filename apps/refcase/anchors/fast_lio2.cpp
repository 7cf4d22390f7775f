// refcase --anchor fast-lio2: FAST-LIO2's forward propagation of one scan (the whole case:
// the previous scan ended on the first sample, this one ends on the last), through the
// kernel's 23-dimensional error state (kernels/fast_lio2.h), for the anchors' two runs:
// `as_fastlio` (gravity on FAST-LIO's S2 of length 9.809) and `case_gravity` (the S2 members
// set to the case's gravity). The noise as FAST-LIO's configuration holds it: each density
// sigma as the per-sample variance sigma^2 200, the anchors' nominal IMU rate; G_m_s2 =
// |mean_acc| = 9.81. The start is state_s with identity extrinsics, P0 = cov_s_left in this
// error state (drot = R_s^T dtheta_left), zero in the extrinsic and gravity blocks.
#include <Eigen/Geometry>
#include <charconv>
#include <string>

#include "anchor_writer.h"
#include "fast_lio2_start.h"
#include "imuconv/kernels/fast_lio2.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;
using namespace anchor_support;

constexpr double kFastLio2ImuRate = 200.0;  // the anchors' nominal rate (their imu_rate)

/// The shortest text that reads back as x (9.81 for the cases' |g|).
std::string ShortestText(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

/// A 23x23 matrix of the error state with its block layout, as the anchor files write it.
json ErrorStateMatrix(const Mat23& m) {
  return {{"order",
           json::array({"pos", "rot", "offset_R_L_I", "offset_T_L_I", "vel", "bg", "ba", "grav"})},
          {"block_sizes", json::array({3, 3, 3, 3, 3, 3, 3, 2})},
          {"definition",
           "pos = pos^ + dpos (world); rot = rot^ Exp(drot) (right, body frame: MTK::SO3 "
           "boxplus); offset_R_L_I likewise; offset_T_L_I, vel (world), bg, ba additive; grav = "
           "Exp(Bx(grav^) dgrav) grav^ (MTK::S2 boxplus, S2_typ = 1 basis S2_Bx); 23 = "
           "3+3+3+3+3+3+3+2"},
          {"matrix", ToJson(m)}};
}

json FastLio2StateJson(const FastLio2State& s) {
  return {{"rot_q_wxyz", Wxyz(s.rot)},
          {"rot_R", ToJson(s.rot.toRotationMatrix())},
          {"offset_R_L_I_q_wxyz", Wxyz(s.offset_R_L_I)},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, s, (pos)(offset_T_L_I)(vel)(bg)(ba))
          {"grav", ToJsonVec(s.grav.vec)},
          {"grav_S2_length", s.grav.length}};
}

json ScanRun(const Case& k, const FastLio2Parameters& params, const FastLio2State& start,
             const Mat23& P0, const char* gravity_setup) {
  const double first = k.samples.front().t, last = k.samples.back().t;
  FastLio2Propagation out;
  Require(PropagateFastLio2Scan(k.samples, params, first, last, start, P0, out),
          "FAST-LIO2 propagation");
  return {{"gravity_setup", gravity_setup},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, out, (n_predict)(sum_dt)(last_predict_dt))
          // the scan ends on the last sample: the frame-end predict's dt is -0.0, a no-op
          {"last_predict_is_noop", out.last_predict_dt == 0.0},
          {"state_end", FastLio2StateJson(out.end)},
          IMUCONV_ANCHOR_MEMBERS(ErrorStateMatrix, out, (covariance)(Phi_summed)(Qd_summed))};
}

json FastLio2(const Registry&, const Case& k) {
  FastLio2Parameters params;  // G_m_s2 = |mean_acc| = 9.81
  const ImuNoise& n = k.noise;
  params.gyr_cov = n.gyro_noise_density * n.gyro_noise_density * kFastLio2ImuRate;
  params.acc_cov = n.accel_noise_density * n.accel_noise_density * kFastLio2ImuRate;
  params.b_gyr_cov = n.gyro_random_walk * n.gyro_random_walk * kFastLio2ImuRate;
  params.b_acc_cov = n.accel_random_walk * n.accel_random_walk * kFastLio2ImuRate;

  FastLio2State start;
  start.pos = k.x_s.p;
  // SO3's constructor from the case's quaternion normalizes it
  start.rot = StartQuaternion(k).normalized();
  start.vel = k.x_s.v;
  start.bg = k.x_s.bg;
  start.ba = k.x_s.ba;

  // P0: cov_s_left's [dp, dtheta, dv, dbg, dba] (R = Exp(dtheta) R^) in this error state.
  const Mat23 P0 = FastLio2StartCovariance(start.rot, k.cov_s_left);

  FastLio2State as_built = start, case_gravity = start;
  as_built.grav = FastLio2GravityAsBuilt(k.gravity);
  case_gravity.grav = FastLio2GravityExact(k.gravity);
  return {{"as_fastlio",
           ScanRun(k, params, as_built, P0,
                   "grav = S2(case gravity): FAST-LIO's S2<double, 98090, 10000, 1> rescales it to "
                   "length 9.809")},
          {"case_gravity", ScanRun(k, params, case_gravity, P0,
                                   ("grav S2 members set to the case gravity (length = |g| = " +
                                    ShortestText(case_gravity.grav.length) +
                                    ", vec = g); everything else identical")
                                       .c_str())}};
}

}  // namespace
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(fast_lio2, "fast-lio2", &FastLio2)
