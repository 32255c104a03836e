#include "symbolic/trace.hpp"

#include "symbolic/trace_inputs.hpp"

#include "solver/outward_sweep.hpp"
#include "solver/solver_sweep.hpp"
#include "solver/state_fields.hpp"
#include "symbolic/symbol.hpp"

namespace sweepgen::symbolic {

Symbol traced_input(Trace& trace, Quantity quantity, std::size_t instance, std::size_t index) {
  trace.inputs.push_back({quantity, static_cast<std::uint32_t>(instance), static_cast<std::uint32_t>(index)});
  return Symbol::from_node(trace.graph.input());
}

// q as generated: a floating base's rotation (9), then the joints' positions; its six
// coordinates have no position (F5), a coupled joint neither position nor velocity (M1).
TracedKinematicsInputs traced_kinematics_inputs(Trace& trace, const model::Chain& chain) {
  const std::size_t n = chain.dof(), base = chain.base_coordinates();
  const std::size_t rotation = base > 0 ? 9 : 0;
  TracedKinematicsInputs in{spatial::Mat3<Symbol>::Identity(), solver::JointVector<Symbol>(n),
                            solver::JointVector<Symbol>(n)};
  for (std::size_t r = 0; r < rotation; ++r)
    in.base_rotation(static_cast<Eigen::Index>(r / 3), static_cast<Eigen::Index>(r % 3)) =
        traced_input(trace, Quantity::base_rotation, 0, r);
  std::size_t coupled = 0;  // coupled joints before joint i + 1
  for (std::size_t i = 0; i < n; ++i) {
    if (chain.coupling_of(i + 1) != nullptr) {
      ++coupled;
      continue;
    }
    if (i >= base) in.q[i] = traced_input(trace, Quantity::joint_position, 0, rotation + i - base - coupled);
    in.qd[i] = traced_input(trace, Quantity::joint_velocity, 0, i - coupled);
  }
  return in;
}

solver::DriverInputs<Symbol> traced_driver_inputs(Trace& trace, const solver::DriverLayout& layout, std::size_t n) {
  auto drivers = solver::DriverInputs<Symbol>::sized(layout, n);
  for (std::size_t t = 0; t < layout.torques.size(); ++t)
    for (std::size_t i = 0; i < n; ++i)
      drivers.torques[t][i] = traced_input(trace, Quantity::feedforward_torque, t, i);
  for (std::size_t e = 0; e < layout.external_forces.size(); ++e) {
    auto& f = drivers.external_forces[e];
    for (int c = 0; c < 3; ++c) {
      f.moment[c] = traced_input(trace, Quantity::external_force, e, static_cast<std::size_t>(c));
      f.force[c] = traced_input(trace, Quantity::external_force, e, static_cast<std::size_t>(3 + c));
    }
  }
  // α: constants where the set fixes them, else inputs numbered over the run-time directions.
  std::size_t k = 0, run_time = 0;
  for (const auto& set : layout.constraint_sets())
    for (std::size_t d = 0; d < set.count; ++d, ++k) {
      auto& alpha = drivers.constraint_directions[k];
      for (int c = 0; c < 3; ++c) {
        if (set.directions_fixed()) {
          alpha.moment[c] = Symbol(set.fixed[d].moment[c]);
          alpha.force[c] = Symbol(set.fixed[d].force[c]);
        } else {
          alpha.moment[c] = traced_input(trace, Quantity::constraint_direction, run_time, static_cast<std::size_t>(c));
          alpha.force[c] = traced_input(trace, Quantity::constraint_direction, run_time, static_cast<std::size_t>(3 + c));
        }
      }
      if (!set.directions_fixed()) ++run_time;
    }
  return drivers;
}

solver::ConstraintVector<Symbol> traced_setpoints(Trace& trace, std::size_t nc) {
  solver::ConstraintVector<Symbol> beta(nc);
  for (std::size_t k = 0; k < nc; ++k) beta[k] = traced_input(trace, Quantity::energy_setpoint, 0, k);
  return beta;
}

void canonicalise(Trace& trace) {
  // Ids independent of the compiler that built sweepgen (Graph::canonical).
  std::vector<NodeId> roots;
  for (const Field& field : trace.fields) roots.push_back(field.node);
  trace.graph = trace.graph.canonical(roots);
  for (std::size_t i = 0; i < roots.size(); ++i) trace.fields[i].node = roots[i];
}

Stage stage_of(Quantity quantity) {
  switch (quantity) {
    case Quantity::joint_position:
    case Quantity::base_rotation:
    case Quantity::joint_velocity: return stage_outward;
    case Quantity::feedforward_torque:
    case Quantity::external_force:
    case Quantity::constraint_direction: return stage_decompose;
    case Quantity::energy_setpoint: return stage_solve;
  }
  return stage_solve;
}

Trace trace_solver(const model::Chain& chain, const TraceRequest& request) {
  Trace trace;
  Graph& g = trace.graph;
  TraceScope scope(g);
  const solver::DriverLayout& layout = request.layout;
  const solver::SolverModel<Symbol> model(chain, layout, request.options, request.epsilon);
  const std::size_t n = model.dof(), nc = model.constraints();
  trace.layout = layout;
  trace.dof = n;
  trace.constraints = nc;
  trace.policies = request.policies;

  const TracedKinematicsInputs in = traced_kinematics_inputs(trace, chain);
  auto kin = solver::KinematicsState<Symbol>::sized(n);
  solver::outward_sweep_base_to_tip(model, in.q, in.qd, kin, in.base_rotation);

  const solver::DriverInputs<Symbol> drivers = traced_driver_inputs(trace, layout, n);
  trace.constraint_rows = request.options.constraint_rows;
  auto art = solver::ArticulatedState<Symbol>::sized(n, nc, layout.tracks.size());
  solver::decomposition_sweep_tip_to_base(model, kin, drivers, art);

  const solver::ConstraintVector<Symbol> beta = traced_setpoints(trace, model.set_directions());

  const auto record = [&trace, &request](const std::string& group, bool solution) {
    return [&trace, &request, group, solution](const std::string& array, int body, int component, const Symbol& value) {
      trace.fields.push_back({group, array, body, component, value.id(),
                              solution && solver::is_solution_output(array, request.outputs)});
    };
  };
  solver::visit_fields(kin, record("kinematics", false));
  solver::visit_fields(art, layout, record("articulated", false));
  for (solver::Policy policy : request.policies) {
    auto solution = solver::Solution<Symbol>::sized(n, nc, layout.listed_sets(), 0, model.couplings.size());
    solver::solver_sweep_base_to_tip(model, kin, art, drivers, beta, policy, solution);
    solver::visit_fields(solution, policy, record(solver::name(policy), true));
  }
  canonicalise(trace);
  return trace;
}

}  // namespace sweepgen::symbolic
