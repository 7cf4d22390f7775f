#include "imuconv/optimize/optimize_output.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "imuconv/pipeline/json_io.h"

namespace imuconv::optimize {

namespace {

nlohmann::json Vec(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json Quaternion(const Mat3& R) {
  const Eigen::Vector4d q = UnitQuaternionWxyz(R);
  return {q[0], q[1], q[2], q[3]};
}

// The 1-sigma of axis `a` of block `label` (NaN without covariance).
double Sigma(const Result& r, const Keyframe& k, const char* label, int a) {
  if (!r.covariance_ok) return std::nan("");
  int offset = 0;
  for (std::size_t b = 0; b < r.labels.size(); ++b)
    if (r.labels[b] == label) offset = static_cast<int>(3 * b);
  return std::sqrt(k.cov(offset + a, offset + a));
}

}  // namespace

int TotalIterations(const Result& r) {
  return std::accumulate(r.rounds.begin(), r.rounds.end(), 0,
                         [](int s, const Round& rd) { return s + rd.iterations; });
}

double TotalSeconds(const Result& r) {
  return std::accumulate(r.rounds.begin(), r.rounds.end(), 0.0,
                         [](double s, const Round& rd) { return s + rd.seconds; });
}

nlohmann::json RoundsJson(const Result& r) {
  nlohmann::json rounds = nlohmann::json::array();
  for (const Round& rd : r.rounds)
    rounds.push_back({{"iterations", rd.iterations},
                      {"initial_cost", rd.initial_cost},
                      {"final_cost", rd.final_cost},
                      {"termination", rd.termination},
                      {"seconds", rd.seconds},
                      {"reintegrated", rd.reintegrated}});
  return rounds;
}

nlohmann::json ResultJson(const Result& r) {
  nlohmann::json j;
  j["method"] = r.method;
  j["convention"] = r.convention;
  j["residual_kind"] = r.kind;
  j["keyframe_step"] = r.keyframe_step;
  j["noise"] = {{"gyro_noise_density", r.noise.gyro_noise_density},
                {"accel_noise_density", r.noise.accel_noise_density},
                {"gyro_random_walk", r.noise.gyro_random_walk},
                {"accel_random_walk", r.noise.accel_random_walk}};
  j["blocks"] = r.labels;
  j["solver"] = {{"converged", r.converged},
                 {"termination", r.rounds.empty() ? "" : r.rounds.back().termination},
                 {"message", r.solver_message},
                 {"iterations", TotalIterations(r)},
                 {"initial_cost", r.rounds.empty() ? 0.0 : r.rounds.front().initial_cost},
                 {"final_cost", r.rounds.empty() ? 0.0 : r.rounds.back().final_cost},
                 {"seconds", TotalSeconds(r)},
                 {"factors", r.factors},
                 {"rounds", RoundsJson(r)},
                 {"pending_reintegration", r.pending_reintegration}};
  j["covariance"] = {{"computed", r.covariance_ok},
                     {"message", r.covariance_message},
                     {"seconds", r.covariance_seconds}};
  nlohmann::json kfs = nlohmann::json::array();
  for (const Keyframe& k : r.keyframes) {
    nlohmann::json o = {{"t", k.t},        {"p", Vec(k.x.p)},   {"q_wxyz", Quaternion(k.x.R)},
                        {"v", Vec(k.x.v)}, {"bg", Vec(k.x.bg)}, {"ba", Vec(k.x.ba)}};
    o["cov"] = r.covariance_ok ? pipeline::MatrixToJson(k.cov) : nlohmann::json(nullptr);
    if (k.has_reference_bias) {
      o["reference_bg"] = Vec(k.ref_bg);
      o["reference_ba"] = Vec(k.ref_ba);
    }
    kfs.push_back(std::move(o));
  }
  j["keyframes"] = std::move(kfs);
  if (r.has_reference_bias && r.covariance_ok)
    j["bias_vs_reference"] = {{"rms_bg", Vec(r.bias.rms_bg)},
                              {"rms_ba", Vec(r.bias.rms_ba)},
                              {"within_3sigma_bg", Vec(r.bias.within_3sigma_bg)},
                              {"within_3sigma_ba", Vec(r.bias.within_3sigma_ba)}};
  return j;
}

void PrintTable(std::ostream& out, const Result& r) {
  char buf[512];
  out << "optimize: method " << r.method << ", convention " << r.convention << ", residual "
      << r.kind << ", " << r.keyframes.size() << " keyframes every " << r.keyframe_step << " s, "
      << r.factors << " preintegration factors\n";
  out << "solver: " << (r.converged ? "converged" : "DID NOT CONVERGE") << " ("
      << (r.rounds.empty() ? "" : r.rounds.back().termination) << ": " << r.solver_message << ")\n";
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& rd = r.rounds[i];
    std::snprintf(buf, sizeof buf,
                  "  solve %zu: %d iterations, cost %.6g -> %.6g, %.3f s, then %d factors "
                  "re-integrated\n",
                  i + 1, rd.iterations, rd.initial_cost, rd.final_cost, rd.seconds,
                  rd.reintegrated);
    out << buf;
  }
  if (r.pending_reintegration > 0)
    out << "  " << r.pending_reintegration
        << " factors' biases still moved beyond the thresholds after the last solve "
           "(first-order corrected)\n";
  if (!r.covariance_ok) {
    out << "covariance: " << r.covariance_message << "\n";
  } else {
    std::snprintf(buf, sizeof buf,
                  "covariance: each keyframe's 15x15 marginal in the %s chart, %.3f s\n",
                  r.convention.c_str(), r.covariance_seconds);
    out << buf;
  }
  std::snprintf(buf, sizeof buf, "%10s %10s %10s %10s  %-32s %-32s\n", "t [s]", "p.x", "p.y", "p.z",
                "bg [rad/s] (1 sigma)", "ba [m/s^2] (1 sigma)");
  out << buf;
  for (const Keyframe& k : r.keyframes) {
    std::snprintf(buf, sizeof buf, "%10.4f %10.4f %10.4f %10.4f ", k.t, k.x.p.x(), k.x.p.y(),
                  k.x.p.z());
    out << buf;
    for (const char* label : {"bg", "ba"}) {
      const Vec3& b = std::string(label) == "bg" ? k.x.bg : k.x.ba;
      for (int a = 0; a < 3; ++a) {
        std::snprintf(buf, sizeof buf, " %+.5f(%.1e)", b[a], Sigma(r, k, label, a));
        out << buf;
      }
    }
    out << "\n";
  }
  if (r.has_reference_bias && r.covariance_ok) {
    std::snprintf(buf, sizeof buf,
                  "against the poses file's biases: RMS bg %.2e %.2e %.2e rad/s, ba %.2e %.2e "
                  "%.2e m/s^2; within 3 sigma bg %.2f %.2f %.2f, ba %.2f %.2f %.2f\n",
                  r.bias.rms_bg.x(), r.bias.rms_bg.y(), r.bias.rms_bg.z(), r.bias.rms_ba.x(),
                  r.bias.rms_ba.y(), r.bias.rms_ba.z(), r.bias.within_3sigma_bg.x(),
                  r.bias.within_3sigma_bg.y(), r.bias.within_3sigma_bg.z(),
                  r.bias.within_3sigma_ba.x(), r.bias.within_3sigma_ba.y(),
                  r.bias.within_3sigma_ba.z());
    out << buf;
  }
}

Eigen::Vector4d UnitQuaternionWxyz(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;  // w >= 0, as the CLI's other q_wxyz columns
  return {q.w(), q.x(), q.y(), q.z()};
}

}  // namespace imuconv::optimize
