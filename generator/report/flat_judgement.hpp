// `sweepgen report --scene S --judge FILE`: a solver's flat results computed elsewhere (the
// generated code on a GPU, bench/gpu/run.sh; any build of it), judged state by state against the
// binary128 referee as the stability suite judges the reference solver (docs/stability.md,
// "Errors and condition numbers"; report/stability_errors.hpp).
//
// FILE: one state per line, the scene's flat input then the solver's flat output
// (solver/flat_layout.hpp), in double, as numbers strtod reads (C99 hex floats round-trip
// exactly); blank lines and lines that start with '#' are skipped.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>

#include "scene/scene.hpp"

namespace sweepgen::report {

// The bound on a full-rank state's error, kFlatErrorFactor · eps · κ, κ widened by cond(M(q))
// where the error exceeds it with κ alone (as the generated scenes' tests judge: q̈ near a
// wrist singularity grows with cond(M)): the stability suite's factor (tests/test_stability.cpp,
// measured worst 8.6 there). A state whose bound is beyond kFlatErrorCeiling (κ > 4.5e11 in
// double) is counted, not judged: only its status and finiteness are.
constexpr double kFlatErrorFactor = 100;
constexpr double kFlatErrorCeiling = 1e-2;

struct FlatJudgement {
  std::size_t states = 0;
  std::size_t judged = 0;          // full rank (neither the solve nor the referee dropped or locked), within the ceiling
  std::size_t beyond_ceiling = 0;  // full rank, bound above kFlatErrorCeiling: not judged
  std::size_t not_full_rank = 0;   // a direction dropped or a joint locked: status and finiteness only
  std::size_t over_bound = 0;      // judged and above the bound
  std::size_t status_differs = 0;  // the referee's status bits differ, its decision not borderline
  std::size_t not_finite = 0;      // a NaN or Inf where the referee's results fit in double
  double worst_ratio = 0;          // largest error / (eps κ) over the judged states
  std::size_t worst_state = 0;     // its line's state number (0-based)
  bool passed() const { return over_bound == 0 && status_differs == 0 && not_finite == 0; }
};

// Reads and judges `file` against the scene's referee (with the scene's double tolerances);
// writes a line per failing state and a summary to `out`. Throws InputError naming the
// file, the line and the reason for a line that is not the scene's in and out sizes of numbers.
FlatJudgement judge_flat_results(const scene::Scene& scene, const std::string& file, std::ostream& out);

}  // namespace sweepgen::report
