#include "check.h"

#include <algorithm>
#include <sstream>

#include "../pipeline/src/forms/measurement.h"
#include "../pipeline/src/run_util.h"
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
    c.J_bias_columns = pipeline::BiasLabels(reg.info(PluginKind::IncrementConvention, c.jacobian_convention).blocks);
  c.J_bias_sign = 1;
  return c;
}

// The differences of `e` entry by entry, computed as Explain scored it (explain.cpp): the
// covariance candidate of its convention in its block order on the correlation scale, the
// Jacobian candidate of its row chart with its columns and sign relative above the floor.
BestEntries EntriesOf(const Registry& reg, const SchemeCandidates& s, const UserNumbers& user, const Explanation& e) {
  BestEntries out;
  for (const CovarianceCandidate& c : s.covariances)
    if (c.convention == e.convention) out.cov = CorrelationScaleEntries(Reordered(c, e.blocks), user.cov);
  for (const JacobianCandidate& j : s.jacobians)
    if (j.chart == e.jacobian_convention)
      out.J_bias = RelativeAboveFloorEntries(Arranged(j, e.J_bias_columns, e.J_bias_sign), user.J_bias);
  if (reg.has(PluginKind::IncrementConvention, e.jacobian_convention))
    for (const auto& b : reg.info(PluginKind::IncrementConvention, e.jacobian_convention).blocks)
      if (b != "bg" && b != "ba") out.J_bias_rows.push_back(b);
  return out;
}

}  // namespace

CheckResult RunCheck(const Registry& reg, const CaseInput& input, const std::vector<pipeline::DeclaredMeasurement>& ms,
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
      fail("t_start and t_end (seconds, on the case's time axis) are needed to check a measurement");
    // The interval must lie inside the samples: propagating beyond them would extrapolate.
    // 1e-6 s is the measurements form's own agreement of two statements of one time.
    if (*m.t_s < t_first - 1e-6 || *m.t_e > t_last + 1e-6)
      fail("the interval [" + Seconds(*m.t_s) + ", " + Seconds(*m.t_e) + "] is not inside " + input.source + " [" +
           Seconds(t_first) + ", " + Seconds(t_last) + "]: are these the samples the measurement was made from?");
    std::vector<ReferenceSchemes::Reference> refs;
    try {
      refs = schemes.compute(input.samples, std::max(*m.t_s, t_first), std::min(*m.t_e, t_last), m.in.bg_hat,
                             m.in.ba_hat, input.noise);
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
    r.declared = Declared(reg, m);
    r.jacobian_convention_implied = m.jacobian_convention_implied;
    const Tolerances& tol = CheckTolerances();
    r.under_declaration = Explain(candidates, user, r.declared, tol);
    r.best = Explain(candidates, user, Constraints{}, tol, r.declared);
    // When the declaration explains the numbers, it is the explanation reported (an equally
    // good other one is not better).
    if (Score(r.under_declaration, tol) <= 1.0) r.best = r.under_declaration;
    const auto nearest = std::find_if(candidates.begin(), candidates.end(),
                                      [&](const SchemeCandidates& c) { return c.scheme == r.best.scheme; });
    r.best_entries = EntriesOf(reg, *nearest, user, r.best);
    r.judgement = Judge(r.declared, r.under_declaration, r.best, *nearest, user);
    if (r.judgement.verdict == Verdict::inconsistent) out.verdict = Verdict::inconsistent;
    out.measurements.push_back(std::move(r));
  }
  return out;
}

}  // namespace imuconv::check
