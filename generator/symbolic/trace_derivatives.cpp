#include "symbolic/trace_derivatives.hpp"

#include "solver/derivative_seeds.hpp"
#include "solver/outward_sweep.hpp"
#include "solver/residual_tangents.hpp"
#include "solver/solver_sweep.hpp"
#include "solver/state_fields.hpp"
#include "symbolic/trace_inputs.hpp"

namespace sweepgen::symbolic {
namespace {

using D = solver::Dual<Symbol>;

// One output y of a solve: its values (`name`) and, if `with_jacobian`, its Jacobian (`d_<name>`,
// component r · columns + j: row r, column j of (D2)). What is not recorded is not computed.
template <class Vector>
void record_output(Trace& trace, const std::string& group, const std::string& name, const Vector& y,
                   const solver::DerivativeColumns& columns, bool with_jacobian) {
  for (Eigen::Index r = 0; r < y.size(); ++r)
    trace.fields.push_back({group, name, solver::kBodyless, static_cast<int>(r), y[r].value().id(), true});
  if (!with_jacobian) return;
  for (Eigen::Index r = 0; r < y.size(); ++r)
    for (std::size_t j = 0; j < columns.count(); ++j)
      trace.fields.push_back({group, "d_" + name, solver::kBodyless, static_cast<int>(r * columns.count() + j),
                              y[r].derivative(j).id(), true});
}

}  // namespace

Trace trace_derivatives(const model::Chain& chain, const TraceRequest& request, const solver::DerivativeOutputs& outputs) {
  Trace trace;
  TraceScope scope(trace.graph);
  const solver::DriverLayout& layout = request.layout;
  const solver::SolverModel<D> model(chain, layout, request.options, request.epsilon);
  // nc: every direction, the couplings' among them; sets: the β inputs (D2).
  const std::size_t n = model.dof(), nc = model.constraints(), sets = model.set_directions();
  const std::size_t base = model.base_coordinates();
  const auto columns = solver::DerivativeColumns::of(n, sets, model.couplings);
  trace.layout = layout;
  trace.dof = n;
  trace.constraints = nc;
  for (solver::Policy policy : request.policies)
    if (solver::differentiable(policy)) trace.policies.push_back(policy);

  // The generated code's inputs, seeded along (D2)'s columns.
  const TracedKinematicsInputs in = traced_kinematics_inputs(trace, chain);
  const solver::SeededKinematics<Symbol> seeds = solver::seeded_kinematics(in.q, in.qd, in.base_rotation, base, columns);
  const solver::JointVector<D>& q = seeds.q;
  const solver::JointVector<D>& qd = seeds.qd;
  const spatial::Mat3<D>& base_rotation = seeds.base_rotation;
  auto kin = solver::KinematicsState<D>::sized(n);
  solver::outward_sweep_base_to_tip(model, q, qd, kin, base_rotation);
  // (D5): the sweeps of the τff and β columns read q, q̇ without tangent.
  auto kin_values = solver::KinematicsState<D>::sized(n);
  const solver::JointVector<D> qd_values = solver::values_of<Symbol>(qd);
  solver::outward_sweep_base_to_tip(model, solver::values_of<Symbol>(q), qd_values, kin_values,
                                    solver::values_of<Symbol>(base_rotation));

  const solver::DriverInputs<Symbol> symbols = traced_driver_inputs(trace, layout, n);
  auto drivers = solver::DriverInputs<D>::sized(layout, n);
  for (std::size_t t = 0; t < layout.torques.size(); ++t)
    for (std::size_t i = 0; i < n; ++i)
      drivers.torques[t][i] = t == 0 ? solver::seeded(symbols.torques[t][i], columns.tau_ff(i), columns) : D(symbols.torques[t][i]);
  for (std::size_t e = 0; e < layout.external_forces.size(); ++e)
    drivers.external_forces[e] = {symbols.external_forces[e].moment.cast<D>(), symbols.external_forces[e].force.cast<D>()};
  for (std::size_t k = 0; k < sets; ++k)
    drivers.constraint_directions[k] = {symbols.constraint_directions[k].moment.cast<D>(),
                                        symbols.constraint_directions[k].force.cast<D>()};
  const auto decomposed = [&](const solver::KinematicsState<D>& sweep_kin) {
    auto art = solver::ArticulatedState<D>::sized(n, nc, layout.tracks.size());
    solver::decomposition_sweep_tip_to_base(model, sweep_kin, drivers, art);
    return art;
  };
  const auto art = decomposed(kin);

  const solver::ConstraintVector<Symbol> beta_symbols = traced_setpoints(trace, sets);
  solver::ConstraintVector<D> beta(sets);
  for (std::size_t k = 0; k < sets; ++k) beta[k] = solver::seeded(beta_symbols[k], columns.beta(k), columns);

  // The sweeps' values, as in the solve's trace: they name and anchor (banner) what the
  // derivative functions compute; they are not stored.
  const auto record = [&trace](const std::string& group) {
    return [&trace, group](const std::string& array, int body, int component, const D& value) {
      trace.fields.push_back({group, array, body, component, value.value().id(), false});
    };
  };
  solver::visit_fields(kin, record("kinematics"));
  solver::visit_fields(art, layout, record("articulated"));
  for (solver::Policy policy : trace.policies) {
    auto solution = solver::Solution<D>::sized(n, nc, layout.listed_sets(), 0, model.couplings.size());
    const bool by_residuals = solver::differentiates_by_residuals(model, policy);
    if (by_residuals)
      solver::solver_sweep_base_to_tip(model, kin_values, decomposed(kin_values), drivers, beta, policy, solution);
    else
      solver::solver_sweep_base_to_tip(model, kin, art, drivers, beta, policy, solution);
    solver::mirror_symmetric_columns(solution.qdd, solution.nu, columns);  // (D7)
    if (by_residuals)
      solver::visit_fields(solver::complete_by_residuals(model, kin_values, qd_values, kin, drivers, solution),
                           record(solver::name(policy)));
    const std::string group = solver::name(policy);
    record_output(trace, group, "qdd", solution.qdd, columns, outputs.qdd);
    record_output(trace, group, "nu", solver::ConstraintVector<D>(solution.nu.head(static_cast<Eigen::Index>(sets))), columns,
                  outputs.nu);  // the sets' (D2): no coupling torque
    record_output(trace, group, "tau_cmd", solution.tau_cmd, columns, outputs.tau_cmd);
    trace.fields.push_back({group, "dropped_pivots", solver::kBodyless, 0, solution.dropped_pivots.value().id(), true});
    trace.fields.push_back({group, "locked_joints", solver::kBodyless, 0, solution.locked_joints.value().id(), true});
  }
  canonicalise(trace);
  return trace;
}

}  // namespace sweepgen::symbolic
