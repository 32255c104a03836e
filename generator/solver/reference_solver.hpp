// The generic reference ACHD solver: the sweeps of this folder behind one object that owns
// its state. Every buffer is sized at construction; outward(), decompose() and solve() do
// not allocate. The sweeps are separately callable: outward + decompose once, then any number
// of solve() calls with other policies or setpoints.
#pragma once

#include "model/chain.hpp"
#include "solver/outward_sweep.hpp"
#include "solver/solve_inputs.hpp"
#include "solver/solver_sweep.hpp"

namespace sweepgen::solver {

template <class Scalar>
class ReferenceSolver {
 public:
  ReferenceSolver(const model::Chain& chain, const DriverLayout& layout, const SolverOptions& options = {});

  const SolverModel<Scalar>& model() const { return model_; }
  std::size_t dof() const { return model_.dof(); }

  // Outward sweep for joint positions and velocities (N each; a floating base's first six q are
  // not read, its orientation world_R_base is `base_rotation`, F5; a coupled <mimic> joint's q and
  // q̇ are not read, M1).
  void outward(const JointVector<Scalar>& q, const JointVector<Scalar>& qd,
               const Mat3<Scalar>& base_rotation = Mat3<Scalar>::Identity());
  // Driver values used by the next decompose(); sizes as in the layout.
  DriverInputs<Scalar>& drivers() { return inputs_; }
  // Inward sweep over the layout's tracks (Alg. 1, Alg. 2 or any grouping between).
  void decompose();
  // Solver sweep for setpoints E_cstr,N (the sets' Nc entries) under `policy`.
  const Solution<Scalar>& solve(Policy policy, const ConstraintVector<Scalar>& setpoints);
  unsigned status() const;
  // outward() and decompose() for one problem's values (its drivers copied in).
  void prepare(const SolveInputs<Scalar>& inputs);
  // prepare() and solve() for one problem's values.
  const Solution<Scalar>& run(const SolveInputs<Scalar>& inputs, Policy policy);

  const KinematicsState<Scalar>& kinematics() const { return kinematics_; }
  const ArticulatedState<Scalar>& articulated() const { return articulated_; }
  const Solution<Scalar>& solution() const { return solution_; }

 private:
  SolverModel<Scalar> model_;
  KinematicsState<Scalar> kinematics_;
  ArticulatedState<Scalar> articulated_;
  DriverInputs<Scalar> inputs_;
  Solution<Scalar> solution_;
  // Whether the inputs of the last outward(), decompose() and solve() were free of NaN/Inf.
  bool kinematics_finite_ = true, drivers_finite_ = true, setpoints_finite_ = true;
};

template <class Scalar>
ReferenceSolver<Scalar>::ReferenceSolver(const model::Chain& chain, const DriverLayout& layout,
                                         const SolverOptions& options)
    : model_(chain, layout, options, static_cast<double>(std::numeric_limits<Scalar>::epsilon())),
      kinematics_(KinematicsState<Scalar>::sized(model_.dof(), model_.constraint_sets.size())),
      articulated_(ArticulatedState<Scalar>::sized(model_.dof(), model_.constraints(), layout.tracks.size())),
      inputs_(DriverInputs<Scalar>::sized(layout, model_.dof())),
      solution_(Solution<Scalar>::sized(model_.dof(), model_.constraints(), layout.listed_sets(), layout.loop_sets(),
                                        model_.couplings.size())) {}

template <class Scalar>
void ReferenceSolver<Scalar>::outward(const JointVector<Scalar>& q, const JointVector<Scalar>& qd,
                                      const Mat3<Scalar>& base_rotation) {
  outward_sweep_base_to_tip(model_, q, qd, kinematics_, base_rotation);
  kinematics_finite_ = all_finite(q.tail(q.size() - model_.base_coordinates())) && all_finite(qd) &&
                       (!model_.floating_base || all_finite(base_rotation));
}

template <class Scalar>
void ReferenceSolver<Scalar>::decompose() {
  decomposition_sweep_tip_to_base(model_, kinematics_, inputs_, articulated_);
  drivers_finite_ = true;
  for (const auto& tau : inputs_.torques) drivers_finite_ = drivers_finite_ && all_finite(tau);
  for (const auto& f : inputs_.external_forces) drivers_finite_ = drivers_finite_ && all_finite(f.moment) && all_finite(f.force);
  for (std::size_t k = 0; k < model_.constraints(); ++k)
    drivers_finite_ = drivers_finite_ && all_finite(inputs_.constraint_directions[k].moment) &&
                      all_finite(inputs_.constraint_directions[k].force);
}

template <class Scalar>
const Solution<Scalar>& ReferenceSolver<Scalar>::solve(Policy policy, const ConstraintVector<Scalar>& setpoints) {
  solver_sweep_base_to_tip(model_, kinematics_, articulated_, inputs_, setpoints, policy, solution_);
  setpoints_finite_ = all_finite(setpoints);
  return solution_;
}

template <class Scalar>
void ReferenceSolver<Scalar>::prepare(const SolveInputs<Scalar>& in) {
  outward(in.q, in.qd, in.base_rotation);
  for (std::size_t t = 0; t < in.torques.size(); ++t) inputs_.torques[t] = in.torques[t];
  for (std::size_t e = 0; e < in.wrenches.size(); ++e) inputs_.external_forces[e] = in.wrenches[e];
  for (std::size_t k = 0; k < in.alpha.size(); ++k) inputs_.constraint_directions[k] = in.alpha[k];
  decompose();
}

template <class Scalar>
const Solution<Scalar>& ReferenceSolver<Scalar>::run(const SolveInputs<Scalar>& in, Policy policy) {
  prepare(in);
  return solve(policy, in.beta);
}

template <class Scalar>
unsigned ReferenceSolver<Scalar>::status() const {
  unsigned s = status_ok;
  if (solution_.dropped_pivots > Scalar(0)) s |= status_constraint_rank_deficient;
  if (solution_.locked_joints > Scalar(0)) s |= status_joint_inertia_singular;
  for (Eigen::Index i = 0; i < solution_.saturated.size(); ++i)
    if (solution_.saturated[i] > Scalar(0)) s |= status_saturated;
  const Solution<Scalar>& r = solution_;
  const bool finite = kinematics_finite_ && drivers_finite_ && setpoints_finite_ && all_finite(r.qdd) &&
                      all_finite(r.tau_cmd) && all_finite(r.tau_ctrl) && all_finite(r.nu) &&
                      all_finite(r.tip_acceleration.angular) && all_finite(r.tip_acceleration.linear);
  bool sets_finite = true;
  for (const auto& a : r.set_acceleration) sets_finite = sets_finite && all_finite(a.angular) && all_finite(a.linear);
  for (const auto& e : r.closure_error)
    for (const auto& m : e) sets_finite = sets_finite && all_finite(m.angular) && all_finite(m.linear);
  if (!sets_finite) s |= status_not_finite;
  if (!finite) s |= status_not_finite;
  return s;
}

// Compiled once, for double and float in reference_solver.cpp of sweepgen_core and for long double
// (the tests') in reference_solver_long_double.cpp of sweepgen_test_solvers: a translation unit
// that includes this header does not instantiate (and optimise) the sweeps again. Other scalars (Quad, the symbolic one) instantiate where they are used.
extern template class ReferenceSolver<double>;
extern template class ReferenceSolver<float>;
extern template class ReferenceSolver<long double>;

}  // namespace sweepgen::solver
