// Writes one planned function as straight-line C++: the derivation body by body under a
// banner naming link and joint, each stored quantity tagged with its equation. Inputs and
// earlier results are loaded into locals right before their first use, and each stored value
// is stored right after it is computed (short live ranges: fewer spills, see bench/README.md).
// Values used once are written inline; values used more than once, and every named quantity,
// get a `const` local. What only one path of a select_path needs (Plan::guard) is written
// inside an if/else on its condition; the select_path results are assigned in both branches.
#pragma once

#include <string>

#include "emit/function_plan.hpp"
#include "emit/op_count.hpp"
#include "model/chain.hpp"

namespace sweepgen::emit {

struct FunctionText {
  std::string body;  // statements, indented by two spaces
  OpCount ops;       // on the usual path: the taken branch of every if/else of a path condition (C4)
  OpCount worst;     // the costlier branch of each (equal to `ops` without path conditions)
  // Statements computing a group of lanes (lane_groups.hpp; the seeds' gathers not counted): the
  // function computes in lanes where it has one.
  std::size_t vector_expressions = 0;
};

FunctionText write_function(const symbolic::Trace& trace, const Plan& plan, const FunctionPlan& function,
                            const model::Chain& chain, const std::string& scalar);

}  // namespace sweepgen::emit
