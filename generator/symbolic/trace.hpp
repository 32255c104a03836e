// Runs the reference sweeps with the symbolic scalar: the equations exist once, in
// generator/solver, and the generated code is what they compute for one robot and scene.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "solver/drivers.hpp"
#include "solver/flat_layout.hpp"
#include "solver/policy.hpp"
#include "solver/solver_model.hpp"
#include "symbolic/graph.hpp"

namespace sweepgen::symbolic {

// Which generated function an input feeds; a node belongs to the latest stage among its
// inputs, so each function computes exactly what depends on its own arguments.
enum Stage : int {
  stage_constant = 0,
  stage_outward = 1,    // q (with a floating base's rotation), q̇
  stage_decompose = 2,  // τff, F_ext, α (when not fixed)
  stage_solve = 3,      // E_cstr (β)
};

// What an input of the traced solve stands for, in the math's terms (the emitter spells it).
enum class Quantity : std::uint8_t {
  joint_position,        // q_i: index = its place in the generated q (the joint, 0-based; after
                         // the base rotation for a floating base)
  base_rotation,         // world_R_base of a floating base, row-major: index = its place in q (0..8)
  joint_velocity,        // q̇_i: index = joint
  feedforward_torque,    // τff of torque driver `instance` (DriverLayout::torques): index = joint
  external_force,        // F_ext of driver `instance` (DriverLayout::external_forces): index = component
  constraint_direction,  // α_k, k = `instance`: index = component [moment; force]
  energy_setpoint,       // E_cstr,k = β_k: index = k
};

struct Input {
  Quantity quantity;
  std::uint32_t instance = 0;
  std::uint32_t index = 0;
};

// The generated function that receives an input.
Stage stage_of(Quantity quantity);

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
  std::vector<Input> inputs;  // by Node::input
  solver::DriverLayout layout;
  std::size_t dof = 0;
  std::size_t constraints = 0;
  std::vector<solver::Policy> policies;
  solver::ConstraintRows constraint_rows = solver::ConstraintRows::inward_columns;  // (I2) or (I6)
  std::vector<Field> fields;  // in the order the sweeps compute them
};

struct TraceRequest {
  solver::DriverLayout layout;
  std::vector<solver::Policy> policies;
  solver::SolverOptions options;
  double epsilon = 0;  // of the scalar the code will run in
  solver::SolveOutputs outputs;  // the Solution arrays returned (scene key outputs)
};

Trace trace_solver(const model::Chain& chain, const TraceRequest& request);

}  // namespace sweepgen::symbolic
