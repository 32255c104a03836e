#include "symbolic/trace.hpp"

#include "solver/outward_sweep.hpp"
#include "solver/solver_sweep.hpp"
#include "solver/state_fields.hpp"
#include "symbolic/symbol.hpp"

namespace sweepgen::symbolic {
namespace {

Symbol input(Graph& graph, const std::string& name, Stage stage) { return Symbol::from_node(graph.input(name, stage)); }

std::string indexed(const std::string& array, std::size_t i) { return array + "[" + std::to_string(i) + "]"; }

}  // namespace

Trace trace_solver(const model::Chain& chain, const TraceRequest& request) {
  Trace trace;
  Graph& g = trace.graph;
  TraceScope scope(g);
  const solver::DriverLayout& layout = request.layout;
  const solver::SolverModel<Symbol> model(chain, layout, request.options, request.epsilon);
  const std::size_t n = model.dof(), nc = model.constraints();
  trace.dof = n;
  trace.constraints = nc;
  trace.policies = request.policies;

  solver::JointVector<Symbol> q(n), qd(n);
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = input(g, indexed("q", i), stage_outward);
    qd[i] = input(g, indexed("qd", i), stage_outward);
  }
  auto kin = solver::KinematicsState<Symbol>::sized(n);
  solver::outward_sweep_base_to_tip(model, q, qd, kin);

  auto drivers = solver::DriverInputs<Symbol>::sized(layout, n);
  for (std::size_t t = 0; t < layout.torques.size(); ++t)
    for (std::size_t i = 0; i < n; ++i)
      drivers.torques[t][i] = input(g, indexed("drivers." + layout.torques[t], i), stage_decompose);
  for (std::size_t e = 0; e < layout.external_forces.size(); ++e) {
    const std::string name = "drivers." + layout.external_forces[e].name;
    auto& f = drivers.external_forces[e];
    for (int c = 0; c < 3; ++c) {
      f.moment[c] = input(g, indexed(name, c), stage_decompose);
      f.force[c] = input(g, indexed(name, 3 + c), stage_decompose);
    }
  }
  for (std::size_t k = 0; k < nc; ++k) {
    auto& alpha = drivers.constraint_directions[k];
    for (int c = 0; c < 3; ++c) {
      if (request.fixed_directions.empty()) {
        alpha.moment[c] = input(g, indexed(indexed("drivers.alpha", k), c), stage_decompose);
        alpha.force[c] = input(g, indexed(indexed("drivers.alpha", k), 3 + c), stage_decompose);
      } else {
        alpha.moment[c] = Symbol(request.fixed_directions[k].moment[c]);
        alpha.force[c] = Symbol(request.fixed_directions[k].force[c]);
      }
    }
  }
  auto art = solver::ArticulatedState<Symbol>::sized(n, nc, layout.tracks.size());
  solver::decomposition_sweep_tip_to_base(model, kin, drivers, art);

  solver::ConstraintVector<Symbol> beta(nc);
  for (std::size_t k = 0; k < nc; ++k) beta[k] = input(g, indexed("beta", k), stage_solve);

  const auto record = [&trace](const std::string& group, bool solution) {
    return [&trace, group, solution](const std::string& array, int body, int component, const Symbol& value) {
      trace.fields.push_back(
          {group, array, body, component, value.id(), solution && solver::is_solution_output(array)});
    };
  };
  solver::visit_fields(kin, record("kinematics", false));
  solver::visit_fields(art, layout, record("articulated", false));
  for (solver::Policy policy : request.policies) {
    auto solution = solver::Solution<Symbol>::sized(n, nc);
    solver::solver_sweep_base_to_tip(model, kin, art, drivers, beta, policy, solution);
    solver::visit_fields(solution, policy, record(solver::name(policy), true));
  }
  // Ids independent of the compiler that built sweepgen (Graph::canonical).
  std::vector<NodeId> roots;
  for (const Field& field : trace.fields) roots.push_back(field.node);
  trace.graph = trace.graph.canonical(roots);
  for (std::size_t i = 0; i < roots.size(); ++i) trace.fields[i].node = roots[i];
  return trace;
}

}  // namespace sweepgen::symbolic
