// How much work each way of forming the rows r_i = S_i^T F^A_cstr,i takes (docs/derivation.md,
// (I2) and (I6)), counted on the chain before anything is traced: the columns (I2) carry one
// force 6-vector per direction from its set's body in to the base, N Nc steps on a chain with its
// sets at the tip; the rows (I6) carry one motion 6-vector per joint i out to each body beyond i
// that reaches a set, N (N + 1) / 2 steps on a chain with a set at the tip. Each step is one
// transform and projection of a 6-vector either way.
#pragma once

#include <cstddef>

#include "model/chain.hpp"
#include "solver/drivers.hpp"

namespace sweepgen::solver {

struct ConstraintRowSteps {
  std::size_t inward_columns = 0;  // (I2): per direction, the bodies from its set's body to the base
  std::size_t outward_rows = 0;    // (I6): per joint i, i and the bodies beyond it that reach a set
};

// In time linear in the bodies and sets.
ConstraintRowSteps constraint_row_steps(const model::Chain& chain, const DriverLayout& layout);

}  // namespace sweepgen::solver
