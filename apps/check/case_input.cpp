#include "imuconv/check/case_input.h"

#include <algorithm>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/sample_checks.h"
#include "imuconv/pipeline/timing.h"

namespace imuconv::check {

CaseInput ReadCaseFile(const std::string& path) {
  const pipeline::json doc = pipeline::ParseJsonFile(path);
  pipeline::Checker c(path);
  const pipeline::Node root(doc, "", c);
  CaseInput k;
  // The keys of FORMAT.md: those check does not use are allowed (a case file is read as it
  // is), a misspelt one is not.
  if (!root.expect_object({"case_id", "kind", "gravity", "noise", "imu_columns", "imu", "state_s",
                           "cov_s_left", "end_perturbation", "bias_delta"}))
    c.throw_if_errors();
  if (auto cols = root.get("imu_columns", false))
    if (auto labels = cols->string_list();
        labels && *labels != std::vector<std::string>{"t", "wx", "wy", "wz", "ax", "ay", "az"})
      cols->fail(
          "expected [\"t\", \"wx\", \"wy\", \"wz\", \"ax\", \"ay\", \"az\"] (the only layout check "
          "reads)");
  if (auto imu = root.get("imu", true)) {
    if (!imu->is_array() || imu->size() < 2) {
      imu->fail("expected an array of at least two rows [t, wx, wy, wz, ax, ay, az]");
    } else {
      k.samples.reserve(imu->size());
      for (std::size_t i = 0; i < imu->size(); ++i) {
        const pipeline::Node row = (*imu)[i];
        const auto v = row.vector(7);
        if (!v) break;  // reported; one bad row is enough to say
        ImuSample s;
        s.t = (*v)[0];
        s.gyro = v->segment<3>(1);
        s.accel = v->segment<3>(4);
        if (!k.samples.empty() && !(s.t > k.samples.back().t)) {
          row[0].fail("time " + std::to_string(s.t) +
                      " s does not increase (the previous sample is at " +
                      std::to_string(k.samples.back().t) + " s)");
          break;
        }
        k.samples.push_back(s);
      }
    }
  }
  // The checks every series of samples gets (imuconv/pipeline/sample_checks.h), as `imuconv
  // run` and the Python module make them: a plausible IMU rate (the times are seconds), and
  // no gap above 10 x the median period, which propagation would otherwise integrate across
  // in silence.
  if (c.ok() && k.samples.size() >= 2) {
    if (const auto issue = pipeline::FindSampleIssue(
            k.samples, pipeline::TimingPolicy{}, pipeline::TimeUnit::s, pipeline::TimeSource::imu))
      c.error(issue->index ? "/imu/" + std::to_string(*issue->index) + "/0" : "/imu",
              issue->message);
  }
  if (auto n = root.get("noise", true)) {
    if (n->expect_object({"gyro_noise_density", "accel_noise_density", "gyro_random_walk",
                          "accel_random_walk"})) {
      for (auto [key, dst] :
           {std::pair<const char*, double*>{"gyro_noise_density", &k.noise.gyro_noise_density},
            {"accel_noise_density", &k.noise.accel_noise_density},
            {"gyro_random_walk", &k.noise.gyro_random_walk},
            {"accel_random_walk", &k.noise.accel_random_walk}}) {
        if (auto v = n->number(key, true)) {
          if (*v < 0.0)
            (*n)[key].fail("expected a non-negative density");
          else
            *dst = *v;
        }
      }
    }
  }
  if (c.ok() && k.samples.size() >= 2) {
    double shortest = k.samples[1].t - k.samples[0].t;
    for (std::size_t i = 2; i < k.samples.size(); ++i)
      shortest = std::min(shortest, k.samples[i].t - k.samples[i - 1].t);
    if (const auto issue = pipeline::FindNoiseIssue(k.noise, shortest)) c.error("/noise", *issue);
  }
  c.throw_if_errors();
  return k;
}

}  // namespace imuconv::check
