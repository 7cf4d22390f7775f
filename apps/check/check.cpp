#include "imuconv/check/check.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "imuconv/pipeline/block_labels.h"
#include "imuconv/pipeline/measurement.h"
#include "references.h"

namespace imuconv::check {
namespace {

std::string Seconds(double t) {
  std::ostringstream o;
  o.precision(12);
  o << t;
  return o.str() + " s";
}

/// The declaration as constraints on the search: an undeclared part is free, a declared chart
/// with no order written has its own order (as a pipeline reads it).
Constraints Declared(const Registry& reg, const pipeline::DeclaredMeasurement& m) {
  Constraints c;
  c.convention = m.in.convention;
  c.blocks = m.cov_blocks;
  if (c.blocks.empty() && !m.cov_blocks_unknown && !c.convention.empty())
    c.blocks = reg.info(PluginKind::IncrementConvention, c.convention).blocks;
  c.jacobian_convention = m.in.jacobian_convention;
  c.J_bias_columns = m.J_bias_cols;
  if (c.J_bias_columns.empty() && !m.J_bias_cols_unknown && !c.jacobian_convention.empty())
    c.J_bias_columns = pipeline::BiasLabels(
        reg.info(PluginKind::IncrementConvention, c.jacobian_convention).blocks);
  c.J_bias_sign = 1;
  return c;
}

// The differences of `e` entry by entry, computed as Explain scored it (explain.cpp): the
// covariance candidate of its convention in its block order on the correlation scale, the
// Jacobian candidate of its row chart with its columns and sign relative above the floor.
BestEntries EntriesOf(const Registry& reg, const SchemeCandidates& s, const UserNumbers& user,
                      const Explanation& e) {
  BestEntries out;
  for (const CovarianceCandidate& c : s.covariances)
    if (c.convention == e.convention)
      out.cov = CorrelationScaleEntries(Reordered(c, e.blocks), user.cov);
  for (const JacobianCandidate& j : s.jacobians)
    if (j.chart == e.jacobian_convention)
      out.J_bias =
          RelativeAboveFloorEntries(Arranged(j, e.J_bias_columns, e.J_bias_sign), user.J_bias);
  if (reg.has(PluginKind::IncrementConvention, e.jacobian_convention))
    for (const auto& b : reg.info(PluginKind::IncrementConvention, e.jacobian_convention).blocks)
      if (b != "bg" && b != "ba") out.J_bias_rows.push_back(b);
  return out;
}

std::string CheckShort(double v) {
  std::ostringstream o;
  o.precision(2);
  o << v;
  return o.str();
}

/// The precision and dt findings (issue 23: numbers in single precision are a normal input;
/// a dt that differs is said, not refused). A sum of n steps in a precision of unit round-off
/// u, each addition rounding by at most u times the running sum (at most T = t_end - t_start),
/// differs from T by at most n u T: 2000 steps of 5 ms in float32 (u = 2^-24) by 1.2e-3 s, in
/// double by 2e-12 s. A dt within that bound is what rounding does; one beyond it is wrong, and
/// a factor built on it predicts with the wrong duration: inconsistent.
void PrecisionFindings(MeasurementCheck& r, std::size_t steps) {
  auto& f = r.judgement.findings;
  if (r.float32)
    f.push_back(std::string("the numbers are single precision (") +
                (r.float32_inferred ? "inferred: every number is a float32 value"
                                    : "declared \"precision\": \"float32\"") +
                "): the covariance's symmetry and positive semi-definiteness were judged at 1e-4 "
                "on the correlation "
                "scale, and dt against a float32 sum of the steps");
  if (!r.dt_difference) return;
  const double u = r.float32 ? std::ldexp(1.0, -24) : std::ldexp(1.0, -53);
  const double T = r.t_end - r.t_start;
  r.dt_rounding_bound = static_cast<double>(steps) * u * T;
  const std::string what = "dt = " + Seconds(T + *r.dt_difference) +
                           " differs from t_end - t_start = " + Seconds(T) + " by " +
                           CheckShort(*r.dt_difference) + " s";
  if (std::abs(*r.dt_difference) <= r.dt_rounding_bound) {
    f.push_back(
        what + ", within what a " + (r.float32 ? "float32" : "double") + " sum of the interval's " +
        std::to_string(steps) + " steps can lose (" + CheckShort(r.dt_rounding_bound) +
        " s); check propagates over [t_start, t_end], and a factor using this dt predicts over it");
  } else {
    f.push_back(what + ", more than a " + std::string(r.float32 ? "float32" : "double") +
                " sum of the interval's " + std::to_string(steps) + " steps can lose (" +
                CheckShort(r.dt_rounding_bound) +
                " s): dt is not the interval's duration; fix dt or the times");
    r.judgement.verdict = Verdict::inconsistent;
  }
}

/// The median step between the samples in [t_s, t_e] (0 with fewer than two; 1e-6 s: the
/// measurements form's agreement of two statements of one time).
double MedianPeriod(const std::vector<ImuSample>& samples, double t_s, double t_e) {
  std::vector<double> dt;
  for (std::size_t k = 1; k < samples.size(); ++k)
    if (samples[k - 1].t >= t_s - 1e-6 && samples[k].t <= t_e + 1e-6)
      dt.push_back(samples[k].t - samples[k - 1].t);
  if (dt.empty()) return 0.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

}  // namespace

CheckResult RunCheck(const Registry& reg, const CaseInput& input,
                     const std::vector<pipeline::DeclaredMeasurement>& ms,
                     const std::string& measurements_file) {
  const ReferenceSchemes schemes(reg);
  const double t_first = input.samples.front().t, t_last = input.samples.back().t;
  CheckResult out;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const auto& m = ms[i];
    const auto fail = [&](const std::string& message) {
      throw pipeline::ConfigError(measurements_file, {{m.pointer, message}});
    };
    if (!m.t_s || !m.t_e)
      fail(
          "t_start and t_end (seconds, on the case's time axis) are needed to check a measurement");
    // The interval must lie inside the samples: propagating beyond them would extrapolate.
    // 1e-6 s is the measurements form's own agreement of two statements of one time.
    if (*m.t_s < t_first - 1e-6 || *m.t_e > t_last + 1e-6)
      fail("the interval [" + Seconds(*m.t_s) + ", " + Seconds(*m.t_e) + "] is not inside " +
           input.source + " [" + Seconds(t_first) + ", " + Seconds(t_last) +
           "]: are these the samples the measurement was made from?");
    std::vector<ReferenceSchemes::Reference> refs;
    try {
      refs = schemes.compute(input.samples, std::max(*m.t_s, t_first), std::min(*m.t_e, t_last),
                             m.in.bg_hat, m.in.ba_hat, input.noise);
    } catch (const std::exception& e) {
      fail(std::string("cannot propagate over the interval: ") + e.what());
    }
    MeasurementCheck r;
    std::vector<SchemeCandidates> candidates;
    for (std::size_t s = 0; s < refs.size(); ++s) {
      if (refs[s].m)
        candidates.push_back(MakeCandidates(reg, schemes.ids()[s], *refs[s].m));
      else
        r.not_applicable.emplace_back(schemes.ids()[s], refs[s].not_applicable);
    }
    if (candidates.empty())
      fail("no reference scheme can run over the interval: " + schemes.ids().front() + ": " +
           refs.front().not_applicable);
    UserNumbers user{IncrementEntries(m.in.delta), m.in.J_bias, m.in.cov};

    r.index = i;
    r.pointer = m.pointer;
    r.t_start = *m.t_s;
    r.t_end = *m.t_e;
    r.sample_period = MedianPeriod(input.samples, *m.t_s, *m.t_e);
    r.declared = Declared(reg, m);
    r.jacobian_convention_implied = m.jacobian_convention_implied;
    const Tolerances& tol = CheckTolerances();
    r.under_declaration = Explain(candidates, user, r.declared, tol);
    r.best = Explain(candidates, user, Constraints{}, tol, r.declared);
    // When the declaration explains the numbers, it is the explanation reported (an equally
    // good other one is not better).
    if (Score(r.under_declaration, tol) <= 1.0) r.best = r.under_declaration;
    const auto nearest =
        std::find_if(candidates.begin(), candidates.end(),
                     [&](const SchemeCandidates& c) { return c.scheme == r.best.scheme; });
    r.best_entries = EntriesOf(reg, *nearest, user, r.best);
    r.judgement = Judge(r.declared, r.under_declaration, r.best, *nearest, user, r.sample_period);
    r.float32 = m.precision.float32;
    r.float32_inferred = m.precision.inferred;
    r.dt_difference = pipeline::DtDifference(m);
    std::size_t steps = 0;
    for (std::size_t k = 1; k < input.samples.size(); ++k)
      if (input.samples[k - 1].t >= *m.t_s - 1e-6 && input.samples[k].t <= *m.t_e + 1e-6) ++steps;
    PrecisionFindings(r, steps);
    if (r.judgement.verdict == Verdict::inconsistent) out.verdict = Verdict::inconsistent;
    out.measurements.push_back(std::move(r));
  }
  return out;
}

}  // namespace imuconv::check
