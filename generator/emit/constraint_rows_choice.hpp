// The emitter's choice of (I2) or (I6) (docs/derivation.md): how the rows r_i = S_i^T F^A_cstr,i of a
// scene's constraint are formed, the constraint forces' columns carried inward or the rows
// outward (scene key constraint_rows; bench/README.md, "Constraint columns (I2) or rows (I6)").
#pragma once

#include <string>

#include "emit/function_plan.hpp"
#include "emit/solver_emitter.hpp"
#include "model/chain.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::emit {

// The trace and plan one scalar's code is written from, and the line that says why (empty
// without a constraint).
struct ChosenRows {
  symbolic::Trace trace;
  Plan plan;
  std::string note;
};

// As the scene asks; else both traced (the rows only where their steps allow) and the one of
// lower cost kept, ties to the columns. `trace_request` is the scalar's (its epsilon).
ChosenRows choose_constraint_rows(const model::Chain& chain, const EmitRequest& request,
                                  symbolic::TraceRequest trace_request);

}  // namespace sweepgen::emit
