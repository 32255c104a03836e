// Counted skips: a statistical test that leaves a state out of a comparison says how many it
// left out and why, and fails when their share exceeds what it states. Without this, a change
// that made every state "rank-deficient" (or ill-conditioned) would pass by being skipped.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <utility>

namespace sweepgen::test {

class SkipCount {
 public:
  // `what`: the comparison, for the printed line; `max_share`: the largest share of the
  // considered states that may be skipped (each test says why its value).
  SkipCount(std::string what, double max_share) : what_(std::move(what)), max_share_(max_share) {}
  SkipCount(const SkipCount&) = delete;
  SkipCount& operator=(const SkipCount&) = delete;

  // Counts one considered state; returns `skip`, counting it under `reason` when true.
  bool skip(bool skip, const char* reason) {
    ++considered_;
    if (skip) ++skipped_[reason];
    return skip;
  }
  int considered() const { return considered_; }
  int skipped() const {
    int total = 0;
    for (const auto& [reason, count] : skipped_) total += count;
    return total;
  }

  // Prints "[skips] what: k of n skipped (reason: k, ...), at most s allowed" and asserts the share.
  ~SkipCount() {
    std::string reasons;
    for (const auto& [reason, count] : skipped_)
      reasons += (reasons.empty() ? "" : ", ") + reason + ": " + std::to_string(count);
    std::printf("[skips] %s: %d of %d skipped%s%s%s, at most %.0f%% allowed\n", what_.c_str(), skipped(), considered_,
                reasons.empty() ? "" : " (", reasons.c_str(), reasons.empty() ? "" : ")", 100 * max_share_);
    EXPECT_LE(skipped(), max_share_ * considered_) << what_ << ": too many states skipped (" << reasons << ")";
  }

 private:
  std::string what_;
  double max_share_;
  int considered_ = 0;
  std::map<std::string, int> skipped_;
};

}  // namespace sweepgen::test
