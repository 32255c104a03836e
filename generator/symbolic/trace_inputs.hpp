// The inputs of a traced solve, as graph inputs numbered and described (Trace::inputs) the way the
// generated code reads them: shared by the trace of the solve (trace.cpp) and of its derivatives
// (trace_derivatives.cpp), so both read q, q̇, the drivers and β alike.
#pragma once

#include "model/chain.hpp"
#include "solver/state.hpp"
#include "symbolic/symbol.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::symbolic {

// A new input of `trace` standing for `quantity` (instance, index).
Symbol traced_input(Trace& trace, Quantity quantity, std::size_t instance, std::size_t index);

struct TracedKinematicsInputs {
  spatial::Mat3<Symbol> base_rotation;  // world_R_base (identity for a fixed base)
  solver::JointVector<Symbol> q, qd;    // a floating base's six q and a coupled joint's q, q̇ are not read (0)
};

// q (a floating base's rotation first) and q̇ of `chain`'s joints, numbered as the generated code
// holds them: without the coupled <mimic> joints (M1), whose q and q̇ follow their sources.
TracedKinematicsInputs traced_kinematics_inputs(Trace& trace, const model::Chain& chain);
// τff, F_ext and the run-time α of `layout` (fixed α as constants).
solver::DriverInputs<Symbol> traced_driver_inputs(Trace& trace, const solver::DriverLayout& layout, std::size_t n);
// β, Nc of them.
solver::ConstraintVector<Symbol> traced_setpoints(Trace& trace, std::size_t nc);
// Renumbers the graph from the fields' nodes (Graph::canonical): ids, and so the emitted code,
// independent of the compiler that built sweepgen.
void canonicalise(Trace& trace);

}  // namespace sweepgen::symbolic
