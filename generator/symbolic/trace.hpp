// Runs the reference sweeps with the symbolic scalar: the equations exist once, in
// generator/solver, and the generated code is what they compute for one robot and scene.
#pragma once

#include <string>
#include <vector>

#include "model/chain.hpp"
#include "solver/drivers.hpp"
#include "solver/policy.hpp"
#include "solver/solver_model.hpp"
#include "symbolic/graph.hpp"

namespace sweepgen::symbolic {

// Which generated function an input feeds; a node belongs to the latest stage among its
// inputs, so each function computes exactly what depends on its own arguments.
enum Stage : int {
  stage_constant = 0,
  stage_outward = 1,    // q, q̇
  stage_decompose = 2,  // τff, F_ext, α (when not fixed)
  stage_solve = 3,      // E_cstr (β)
};

struct Field {
  std::string group;  // "kinematics", "articulated" or a policy name
  std::string array;  // name from the math, e.g. "articulated_inertia"
  int body;           // 0..N, or solver::kBodyless
  int component;
  NodeId node;
  bool output;        // an output of a solve (qdd, tau_cmd, ...), always computed
};

struct Trace {
  Graph graph;
  std::size_t dof = 0;
  std::size_t constraints = 0;
  std::vector<solver::Policy> policies;
  std::vector<Field> fields;  // in the order the sweeps compute them
};

struct TraceRequest {
  solver::DriverLayout layout;
  std::vector<spatial::Force<double>> fixed_directions;  // α folded into the code; empty: α is an input
  std::vector<solver::Policy> policies;
  solver::SolverOptions options;
  double epsilon = 0;  // of the scalar the code will run in
};

Trace trace_solver(const model::Chain& chain, const TraceRequest& request);

}  // namespace sweepgen::symbolic
