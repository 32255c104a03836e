// A tolerance for rounding that grows with the condition of the problem, with an absolute
// ceiling: bound(c) = factor · eps · max(1, c), judged only where bound(c) <= ceiling. A state
// beyond the ceiling is not compared (the caller counts it with SkipCount): there any solver in
// that precision may return anything up to the ceiling, and a tolerance that kept growing would
// accept garbage (at c = 1e14, 100 eps c = 2).
#pragma once

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

namespace sweepgen::test {

// Each scalar's domain of validity (docs/stability.md, "Float: domain of validity"): the κ up to
// which the tests judge its results against a multiple of eps κ.
constexpr double kDoubleMaxKappa = 1e8;
constexpr double kFloatMaxKappa = 1e3;

struct RoundingBound {
  double factor;   // multiple of eps c; each use derives it
  double ceiling;  // the largest tolerance ever applied
  double eps = std::numeric_limits<double>::epsilon();

  double operator()(double condition) const { return factor * eps * std::max(1.0, condition); }
  bool judged(double condition) const { return (*this)(condition) <= ceiling; }
};

// The largest error / (eps max(1, c)) seen, printed at the end: how close the suite came to its
// factor (the figure docs and closing notes quote).
class WorstRatio {
 public:
  WorstRatio(std::string what, double eps = std::numeric_limits<double>::epsilon()) : what_(std::move(what)), eps_(eps) {}
  WorstRatio(const WorstRatio&) = delete;
  WorstRatio& operator=(const WorstRatio&) = delete;
  void add(double error, double condition) {
    worst_ = std::max(worst_, error / (eps_ * std::max(1.0, condition)));
    worst_error_ = std::max(worst_error_, error);
  }
  double worst() const { return worst_; }
  ~WorstRatio() {
    std::printf("[rounding] %s: max error %.3e, max error/(eps max(1, cond)) %.3g\n", what_.c_str(), worst_error_, worst_);
  }

 private:
  std::string what_;
  double eps_;
  double worst_ = 0, worst_error_ = 0;
};

}  // namespace sweepgen::test
