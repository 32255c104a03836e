// Why a row of the report has no answer or a large error on a family of states, and whether that
// is what the solver is meant to do there (report.md, per scene, "Why"): from each state's status,
// its referee's, κ and the errors. A newcomer reading err_max = 1 or status 40 % learns whether
// it is a defect or the problem (dependent directions, κ beyond the scalar, a clamp).
#pragma once

#include <string>
#include <vector>

#include "report/study.hpp"

namespace sweepgen::report {

// Why something is as it is, and whether the solver is meant to do that.
struct Finding {
  std::string text;
  bool expected = true;
};

// One finding: on `family`, what happened (`text`, with counts), whether it is expected, and
// the rows it applies to (rows with the same finding share it).
struct Reason {
  std::string family;
  std::string text;
  bool expected = true;
  std::vector<std::string> variants;
};

// Errors above this many ε κ are beyond what the stability suite asserts for the project's own
// solvers (docs/stability.md, "Tolerances and skipped states"; tests/test_stability.cpp).
constexpr double kErrorBoundEpsKappa = 100;

// The findings of every measured row, family by family (SceneStudy::families order).
std::vector<Reason> study_reasons(const SceneStudy& study);

// Why a measured row's err_max and max_residual (every family together) are large, for the notes
// beside them in the summary table: the reason of the state each number comes from, in the
// words of the findings, without counts (rows with the same reason share a note). A text is
// empty where its number is not worth a word: below √ε of the row's scalar and within the bound.
struct RowReasons {
  Finding error, residual;
};
RowReasons row_reasons(const VariantStudy& v);

}  // namespace sweepgen::report
