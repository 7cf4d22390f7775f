// Which rows a reader keeps when only the time range [t0, t1] is needed.
//
// A reader validates every line of a file but keeps only what the tasks use: the rows with
// t in [t0, t1], plus the last row before t0 and the first after t1 (interpolation at t0 and
// t1 needs them). Memory is then bounded by the range asked for, not by the file: a 2 GB CSV
// of which one second is used costs one second of samples.
//
// The timing checks (timing.h) judge the kept rows. Their median period is taken over a window
// of the kept rows plus up to kNeighbours row times on each side (times only, 8 bytes each), so
// that a range holding a handful of rows still has a meaningful median, while the window
// stays small; with no range set, every row is kept and the window is the whole file.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace imuconv::pipeline::data {

template <typename Row>
class RangeKeeper {
 public:
  static constexpr std::size_t kNeighbours = 16;

  explicit RangeKeeper(std::optional<std::pair<double, double>> keep) : keep_(keep) {}

  /// Offers the next row (times strictly increasing).
  void add(double t, std::size_t line, Row row) {
    if (!keep_ || (t >= keep_->first && t <= keep_->second)) {
      push(t, line, std::move(row));
    } else if (t < keep_->first) {
      // Before the range: only the latest row is kept (times increase, so if anything is kept
      // yet, it is that one row); the one it replaces joins the median window.
      if (times_.empty()) {
        push(t, line, std::move(row));
      } else {
        before_.push_back(times_.back());
        if (before_.size() > kNeighbours) before_.pop_front();
        times_.back() = t;
        lines_.back() = line;
        rows_.back() = std::move(row);
      }
    } else if (!after_kept_) {
      push(t, line, std::move(row));
      after_kept_ = true;
    } else if (after_.size() < kNeighbours) {
      after_.push_back(t);
    }
  }

  const std::vector<double>& times() const noexcept { return times_; }
  std::vector<double>& times() noexcept { return times_; }
  const std::vector<std::size_t>& lines() const noexcept { return lines_; }
  std::vector<Row>& rows() noexcept { return rows_; }
  /// Up to kNeighbours row times before the kept rows, the kept rows' times, up to kNeighbours
  /// after: consecutive rows of the file, for the median period.
  std::vector<double> window() const {
    std::vector<double> w(before_.begin(), before_.end());
    w.insert(w.end(), times_.begin(), times_.end());
    w.insert(w.end(), after_.begin(), after_.end());
    return w;
  }

 private:
  void push(double t, std::size_t line, Row row) {
    times_.push_back(t);
    lines_.push_back(line);
    rows_.push_back(std::move(row));
  }
  std::optional<std::pair<double, double>> keep_;
  std::vector<double> times_;
  std::vector<std::size_t> lines_;
  std::vector<Row> rows_;
  std::deque<double> before_;
  std::vector<double> after_;
  bool after_kept_ = false;
};

}  // namespace imuconv::pipeline::data
