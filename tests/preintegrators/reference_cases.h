// Shared by the preintegrator tests: the GTSAM reference cases (tests/data/reference) as
// imuconv inputs, and the max entrywise difference bookkeeping.
#pragma once

#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "imuconv/preintegrator.h"
#include "imuconv/window.h"
#include "imuconv_test.h"
#include "reference_case.h"

namespace imuconv::test {

inline const std::vector<std::string>& ReferenceCaseIds() {
  static const std::vector<std::string> ids(std::begin(kReferenceCaseIds),
                                            std::end(kReferenceCaseIds));
  return ids;
}

/// The window whose knots are exactly `s` (t_s = s.front().t, t_e = s.back().t).
inline SampleWindow WindowOver(const std::vector<ImuSample>& s) {
  SampleWindow w;
  w.samples = s.data();
  w.first = s.front();
  w.last = s.back();
  w.begin = 1;
  w.end = s.size() - 1;
  return w;
}

/// One case file: its samples (owned) and the preintegration input over
/// [first sample, last sample], the interval the reference outputs were made for.
struct ReferenceCase {
  std::string id;
  std::vector<ImuSample> samples;
  ImuNoise noise;
  Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();

  /// The input over all samples; `samples` must outlive it (the window references them).
  /// The window is filled directly (knots = the samples, t_s = first, t_e = last) because
  /// MakeWindow is not exported from imuconv_core.
  PreintegrationInput Input() const {
    return PreintegrationInputOf(WindowOver(samples), bg, ba, noise);
  }

  /// The reference `mid` input: sample k replaced by the mean of samples k and k+1, same
  /// timestamps, so a zero-order hold holds the mean over [t_k, t_k+1]. The last sample's
  /// value is never used by a zero-order hold and is kept as is.
  ReferenceCase Averaged() const {
    ReferenceCase c = *this;
    for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
      c.samples[k].gyro = 0.5 * (samples[k].gyro + samples[k + 1].gyro);
      c.samples[k].accel = 0.5 * (samples[k].accel + samples[k + 1].accel);
    }
    return c;
  }
};

inline ReferenceCase LoadReferenceCase(const std::string& id) {
  const nlohmann::json j = ReadJson(DataPath("reference/cases/" + id + ".json"));
  ReferenceCase c;
  c.id = id;
  c.samples = CaseSamples(j);
  const auto& n = j.at("noise");
  c.noise.gyro_noise_density = n.at("gyro_noise_density").get<double>();
  c.noise.accel_noise_density = n.at("accel_noise_density").get<double>();
  c.noise.gyro_random_walk = n.at("gyro_random_walk").get<double>();
  c.noise.accel_random_walk = n.at("accel_random_walk").get<double>();
  c.bg = JsonVec3(j.at("state_s").at("bg"));
  c.ba = JsonVec3(j.at("state_s").at("ba"));
  return c;
}

/// The worst entrywise difference seen for one field, with where it was.
struct WorstDiff {
  double d = 0.0;
  std::string where;
  void Update(double d_new, const std::string& at) {
    if (where.empty() || d_new > d) {
      d = d_new;
      where = at;
    }
  }
};

/// Max entrywise difference and the (row, col) of its entry.
template <typename A, typename B>
double MaxEntryDiffAt(const Eigen::MatrixBase<A>& ref, const Eigen::MatrixBase<B>& est, int& row,
                      int& col) {
  double m = -1.0;
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index k = 0; k < ref.cols(); ++k) {
      const double d = EntryDiff(ref(i, k), est(i, k));
      if (d > m) {
        m = d;
        row = static_cast<int>(i);
        col = static_cast<int>(k);
      }
    }
  return m;
}

}  // namespace imuconv::test
