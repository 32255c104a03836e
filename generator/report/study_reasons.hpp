// Why a row of the report has no answer or a large error on a family of states, and whether that
// is what the solver is meant to do there (report.md, per scene, "Why"): from each state's status,
// its referee's, κ and the errors. A newcomer reading err_max = 1 or status 40 % learns whether
// it is a defect or the problem (dependent directions, κ beyond the scalar, a clamp).
#pragma once

#include <string>
#include <vector>

#include "report/study.hpp"

namespace sweepgen::report {

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

}  // namespace sweepgen::report
