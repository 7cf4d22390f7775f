// The top-level sources of a pipeline: "imu" (euroc, csv or inline samples) and
// "ground_truth" (sources.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <variant>

#include "../io/message_text.h"
#include "imuconv/pipeline/sample_checks.h"
#include "imuconv/pipeline/timing.h"
#include "sources.h"

namespace imuconv::pipeline {
namespace {

/// A time: a JSON number, or a string with a plain decimal (exact for huge values).
std::optional<TimeValue> TimeFromJson(const Node& n) {
  if (n.value().is_number_integer()) {
    if (auto i = n.integer()) return TimeValue{*i, 0.0};
    return std::nullopt;
  }
  if (n.value().is_number_float()) {
    if (auto d = n.number()) return TimeValueFromDouble(*d);
    return std::nullopt;
  }
  if (n.value().is_string()) {
    if (auto t = ParseTimeValue(n.value().get<std::string>())) return t;
    n.fail("expected a decimal time, found " + QuotedShort(n.value().get<std::string>()));
    return std::nullopt;
  }
  n.fail("expected a time (a number, or a string holding a decimal number), found " +
         TypeName(n.value()));
  return std::nullopt;
}

/// "max_gap_factor" (> 1, default 10) and "allow_gaps" (default false) of an IMU or
/// ground-truth source.
TimingPolicy Timing(const Node& n) {
  TimingPolicy t;
  if (auto fn = n.get("max_gap_factor", false))
    if (auto f = fn->number()) {
      if (!(*f > 1.0))
        fn->fail(
            "expected a number > 1 (a gap longer than this many median sample periods is an "
            "error)");
      else
        t.max_gap_factor = *f;
    }
  if (auto b = n.boolean("allow_gaps", false)) t.allow_gaps = *b;
  return t;
}

/// Inline samples get the checks every series of samples gets (sample_checks.h: finite,
/// increasing, rate, gaps), reported at the sample.
void CheckInlineTiming(const Node& n, const ImuSourceSpec& s) {
  if (s.inline_t.size() < 2 || s.inline_t.size() != s.inline_index.size() ||
      s.inline_raw.size() != s.inline_t.size())
    return;
  TimeOrigin o;
  o.unit = s.csv.time_unit;
  if (s.csv.time_origin) o.value = *s.csv.time_origin;
  std::vector<ImuSample> samples = s.inline_raw;
  for (std::size_t k = 0; k < samples.size(); ++k) samples[k].t = o.relative_seconds(s.inline_t[k]);
  const auto issue = FindSampleIssue(samples, s.timing, s.csv.time_unit, TimeSource::imu);
  if (!issue) return;
  if (issue->index && *issue->index < s.inline_index.size())
    n.checker().error(
        n.child_pointer("samples") + "/" + std::to_string(s.inline_index[*issue->index]) + "/0",
        issue->message);
  else
    n.checker().error(n.child_pointer(n.has("time_unit") ? "time_unit" : "samples"),
                      issue->message);
}

}  // namespace

std::optional<ImuSourceSpec> ReadImuSource(const ParseContext& ctx, const Node& n) {
  if (!n.is_object()) {
    n.fail("expected an object with \"format\": \"euroc\", \"csv\" or \"inline\", found " +
           TypeName(n.value()));
    return std::nullopt;
  }
  ImuSourceSpec s;
  s.pointer = n.pointer();
  const auto fmt = n.get("format", true);
  std::optional<std::string> f;
  if (fmt) f = fmt->one_of({"euroc", "csv", "inline"});
  if (!f) {
    n.expect_object({"format", "path", "time_origin_ns", "delimiter", "header_rows", "comment",
                     "time_unit", "columns", "time_origin", "samples", "max_gap_factor",
                     "allow_gaps"});
    return std::nullopt;
  }
  if (*f == "euroc") {
    s.format = ImuSourceSpec::Format::Euroc;
    n.expect_object({"format", "path", "time_origin_ns", "max_gap_factor", "allow_gaps"});
    if (auto p = n.string("path", true)) s.path = ctx.resolve(*p);
    if (auto o = n.get("time_origin_ns", false)) {
      if (o->value().is_string()) {
        auto t = TimeFromJson(*o);
        if (t && t->frac != 0.0)
          o->fail("expected an integer number of nanoseconds");
        else if (t)
          s.origin_ns = t->whole;
      } else if (auto i = o->integer()) {
        s.origin_ns = *i;
      }
    }
  } else if (*f == "csv") {
    s.format = ImuSourceSpec::Format::Csv;
    n.expect_object({"format", "path", "delimiter", "header_rows", "comment", "time_unit",
                     "columns", "time_origin", "max_gap_factor", "allow_gaps"});
    if (auto p = n.string("path", true)) s.path = ctx.resolve(*p);
    if (auto dn = n.get("delimiter", false)) {
      if (auto d = dn->string()) {
        if (*d == "whitespace")
          s.csv.whitespace_delimited = true;
        else if (d->size() == 1 && (*d)[0] != '"' && (*d)[0] != '\n')
          s.csv.delimiter = (*d)[0];
        else
          dn->fail("expected one character (e.g. \",\", \";\", \"\\t\") or \"whitespace\", found " +
                   QuotedShort(*d));
      }
    }
    if (auto hn = n.get("header_rows", false)) {
      if (auto h = hn->integer()) {
        if (*h < 0 || *h > 1000)
          hn->fail("expected an integer from 0 to 1000");
        else
          s.csv.header_rows = static_cast<int>(*h);
      }
    }
    if (auto cm = n.string("comment", false)) s.csv.comment = *cm;
    if (auto un = n.get("time_unit", false))
      if (auto u = un->one_of({"s", "ms", "us", "ns"})) s.csv.time_unit = *ParseTimeUnit(*u);
    if (auto cn = n.get("columns", true)) {
      std::vector<std::string> names(kImuColumnNames.begin(), kImuColumnNames.end());
      if (cn->expect_object(names)) {
        std::array<bool, 7> given{};
        for (std::size_t k = 0; k < 7; ++k) {
          auto col = cn->get(kImuColumnNames[k], true);
          if (!col) continue;
          if (col->value().is_string()) {
            s.csv.columns[k] = col->value().get<std::string>();
            given[k] = true;
          } else if (col->value().is_number_integer()) {
            const auto i = col->integer();
            if (i && *i >= 0 && *i < 100000) {
              s.csv.columns[k] = static_cast<int>(*i);
              given[k] = true;
            } else {
              col->fail("expected a column index >= 0");
            }
          } else {
            col->fail("expected a 0-based column index or a header name, found " +
                      TypeName(col->value()));
          }
        }
        // Each quantity has its own column: two keys naming one column (the same index, or
        // the same header name) would read one axis twice and give a wrong answer in silence.
        // A name and an index that meet in one column are found by the reader (imu_reader.cpp),
        // which knows the header.
        for (std::size_t k = 1; k < 7; ++k)
          for (std::size_t j = 0; j < k; ++j)
            if (given[j] && given[k] && s.csv.columns[j] == s.csv.columns[k]) {
              const ColumnRef& c = s.csv.columns[k];
              const std::string column =
                  std::holds_alternative<int>(c)
                      ? "column " + std::to_string(std::get<int>(c))
                      : "the column named " + QuotedShort(std::get<std::string>(c));
              cn->checker().error(cn->child_pointer(kImuColumnNames[k]),
                                  column + " is already used for '" +
                                      std::string(kImuColumnNames[j]) +
                                      "'; each of t, wx, wy, wz, ax, ay, az needs its own column");
              break;
            }
      }
    }
    if (auto o = n.get("time_origin", false))
      if (auto t = TimeFromJson(*o)) s.csv.time_origin = *t;
  } else {
    s.format = ImuSourceSpec::Format::Inline;
    s.path = "inline";
    n.expect_object(
        {"format", "samples", "time_unit", "time_origin", "max_gap_factor", "allow_gaps"});
    if (auto un = n.get("time_unit", false))
      if (auto u = un->one_of({"s", "ms", "us", "ns"})) s.csv.time_unit = *ParseTimeUnit(*u);
    if (auto o = n.get("time_origin", false))
      if (auto t = TimeFromJson(*o)) s.csv.time_origin = *t;
    if (auto sn = n.get("samples", true)) {
      if (!sn->is_array() || sn->size() < 2) {
        sn->fail("expected an array of at least 2 samples [t, wx, wy, wz, ax, ay, az]");
      } else {
        for (std::size_t i = 0; i < sn->size(); ++i) {
          const Node row = (*sn)[i];
          if (!row.is_array() || row.size() != 7) {
            row.fail("expected a sample [t, wx, wy, wz, ax, ay, az] (7 numbers), found " +
                     (row.is_array() ? "an array of " + std::to_string(row.size())
                                     : TypeName(row.value())));
            continue;
          }
          const auto t = TimeFromJson(row[0]);
          ImuSample smp;
          bool ok = t.has_value();
          for (std::size_t k = 1; k < 7; ++k) {
            const auto v = row[k].number();
            if (!v) {
              ok = false;
              continue;
            }
            if (k <= 3)
              smp.gyro[static_cast<Eigen::Index>(k - 1)] = *v;
            else
              smp.accel[static_cast<Eigen::Index>(k - 4)] = *v;
          }
          if (!ok) continue;
          if (!s.inline_t.empty()) {
            const TimeValue& prev = s.inline_t.back();
            if (!(t->whole > prev.whole || (t->whole == prev.whole && t->frac > prev.frac))) {
              row[0].fail(
                  "time is not after the previous sample's; sample times must be strictly "
                  "increasing");
              continue;
            }
          }
          s.inline_t.push_back(*t);
          s.inline_raw.push_back(smp);
          s.inline_index.push_back(i);
        }
      }
    }
  }
  s.timing = Timing(n);
  if (s.format == ImuSourceSpec::Format::Inline) CheckInlineTiming(n, s);
  return s;
}

std::optional<GroundTruthSpec> ReadGroundTruthSource(const ParseContext& ctx, const Node& gn) {
  if (!gn.expect_object({"format", "path", "max_gap_factor", "allow_gaps", "T_BS"}))
    return std::nullopt;
  GroundTruthSpec g;
  if (auto fn = gn.get("format", true))
    if (auto f = fn->one_of({"euroc", "euroc_pose", "tum"})) g.format = *f;
  g.pointer = gn.pointer();
  g.timing = Timing(gn);
  if (auto p = gn.string("path", true)) g.path = ctx.resolve(*p);
  if (auto tn = gn.get("T_BS", false)) {
    if (g.format == "euroc") {
      tn->checker().error(
          tn->pointer(),
          "T_BS is for pose files (\"euroc_pose\", \"tum\"): \"euroc\" ground truth is "
          "already the body's state");
    } else if (auto T = tn->matrix(4, 4)) {
      // EuRoC's sensor.yaml gives T_BS with 5 significant digits: its rotation is orthonormal
      // to about 1e-5. Within 1e-4 it is taken as the nearest rotation (by the normalised
      // quaternion); a bottom row other than [0, 0, 0, 1] or a worse rotation is refused.
      const Mat3 R = T->topLeftCorner<3, 3>();
      const double err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
      const bool bottom = (T->row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() == 0.0;
      if (!bottom)
        tn->checker().error(tn->pointer() + "/3", "the last row of T_BS must be [0, 0, 0, 1]");
      else if (!(err <= 1e-4) || R.determinant() <= 0.0)
        tn->checker().error(tn->pointer(),
                            "the rotation of T_BS is not a rotation (|R^T R - I| = " + Num(err, 3) +
                                ", allowed 1e-4, and det > 0)");
      else {
        g.sensor.R_BS = Eigen::Quaterniond(R).normalized().toRotationMatrix();
        g.sensor.p_BS = T->topRightCorner<3, 1>();
      }
    }
  }
  return g;
}

}  // namespace imuconv::pipeline
