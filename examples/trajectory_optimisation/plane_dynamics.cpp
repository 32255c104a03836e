// plane_dynamics.hpp: the generated solver with the plane's direction and stabilising law.
#include "plane_dynamics.hpp"

#include "panda_plane_solver.hpp"

namespace trajopt {
namespace {

namespace gen = panda_plane::f64;
static_assert(panda_plane::dof == kDof && panda_plane::constraints == 1, "panda_plane.yaml: 7 joints, one direction");
static_assert(gen::derivative_columns == kColumns + 1, "columns q, q̇, τff, beta");

constexpr double kGravity = 9.81;  // panda_plane.yaml's default gravity (0, 0, -9.81) [m/s²]

// beta of the law and alpha = [0; Rᵀ n] (Rᵀ n = R's last row) from the hand's state.
template <class T>
void law_terms(const PlaneLaw& law, const HandState<T>& hand, T& beta, Vec3<T>& normal_in_hand) {
  const Vec3<T> w_x_pd = cross(hand.omega, hand.pd);
  beta = T(-law.kd) * hand.pd[2] - T(law.kp) * (hand.p[2] - T(law.height)) - w_x_pd[2] + T(kGravity);
  normal_in_hand = {hand.R[6], hand.R[7], hand.R[8]};
}

gen::Drivers drivers_of(const double* tau, const double* normal_in_hand) {
  gen::Drivers drivers{};
  for (int i = 0; i < kDof; ++i) drivers.tau_ff[i] = tau[i];
  for (int a = 0; a < 3; ++a) {
    drivers.alpha[0][a] = 0;
    drivers.alpha[0][3 + a] = normal_in_hand[a];
  }
  return drivers;
}

}  // namespace

DynamicsValue dynamics(const PlaneLaw& law, const double* q, const double* qd, const double* tau) {
  const HandState<double> hand = hand_state(q, qd);
  double beta;
  Vec3<double> normal;
  law_terms(law, hand, beta, normal);
  const gen::Drivers drivers = drivers_of(tau, normal.data());
  gen::State state;
  gen::Solution solution;
  gen::outward(q, qd, state);
  gen::decompose(drivers, state);
  gen::solve_original(state, &beta, solution);
  DynamicsValue out;
  for (int i = 0; i < kDof; ++i) out.qdd[i] = solution.qdd[i];
  out.nu = solution.nu[0];
  out.status = solution.status;
  return out;
}

DynamicsJacobian dynamics_jacobian(const PlaneLaw& law, const double* q, const double* qd, const double* tau) {
  Dual q_dual[kDof], qd_dual[kDof];
  seed(q, qd, q_dual, qd_dual);
  const HandState<Dual> hand = hand_state(q_dual, qd_dual);
  Dual beta;
  Vec3<Dual> normal;
  law_terms(law, hand, beta, normal);
  const double normal_value[3] = {normal[0].v, normal[1].v, normal[2].v};
  const gen::Drivers drivers = drivers_of(tau, normal_value);

  gen::Derivatives d;
  gen::derivatives_original(q, qd, drivers, &beta.v, d);
  gen::State state;
  gen::Solution solution;  // the hand's acceleration Ẍ_hand, which the turn of alpha meets
  gen::outward(q, qd, state);
  gen::decompose(drivers, state);
  gen::solve_original(state, &beta.v, solution);
  const double* xdd_linear = solution.tip_acceleration + 3;

  // Along q, alpha turns: the setpoint's change ∂β/∂x − (∂α/∂x)ᵀ Ẍ_hand, and the wrench α ν turned by
  // (∂α/∂x) ν, a force R (∂n_b/∂x) ν at the hand, which the joints feel as the torque
  // J_vᵀ R (∂n_b/∂x) ν (J_v's column i: ∂ṗ/∂q̇_i = z_i × (p − o_i)); along q̇, β's change only.
  double beta_change[kTangents], torque_change[kTangents][kDof];
  for (int c = 0; c < kTangents; ++c) {
    beta_change[c] = beta.d[c];
    double force[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
      beta_change[c] -= normal[a].d[c] * xdd_linear[a];
      for (int b = 0; b < 3; ++b) force[a] += hand.R[3 * a + b].v * normal[b].d[c] * d.nu[0];
    }
    for (int i = 0; i < kDof; ++i) {
      torque_change[c][i] = 0;
      for (int a = 0; a < 3; ++a) torque_change[c][i] += hand.pd[a].d[kDof + i] * force[a];
    }
  }
  constexpr int beta_column = kColumns, tau_column = kTangents;
  // Row `row` of a generated Jacobian (q̈'s or ν's) with the turn of alpha and the law added.
  auto total = [&](const double* row, double* out_row) {
    for (int c = 0; c < kTangents; ++c) {
      out_row[c] = row[c] + row[beta_column] * beta_change[c];
      for (int i = 0; i < kDof; ++i) out_row[c] += row[tau_column + i] * torque_change[c][i];
    }
    for (int c = kTangents; c < kColumns; ++c) out_row[c] = row[c];
  };
  DynamicsJacobian out;
  for (int i = 0; i < kDof; ++i) {
    out.qdd[i] = d.qdd[i];
    total(d.d_qdd + i * gen::derivative_columns, out.d_qdd + i * kColumns);
  }
  out.nu = d.nu[0];
  total(d.d_nu, out.d_nu);
  out.status = d.status | solution.status;
  return out;
}

void hand_height(const PlaneLaw& law, const double* q, const double* qd, double& e, double& e_dot,
                 double& e_curvature) {
  Dual q_dual[kDof], qd_dual[kDof];
  seed(q, qd, q_dual, qd_dual);
  const HandState<Dual> hand = hand_state(q_dual, qd_dual);
  e = hand.p[2].v - law.height;
  e_dot = hand.pd[2].v;
  e_curvature = 0;
  for (int j = 0; j < kDof; ++j) e_curvature += hand.pd[2].d[j] * qd[j];
}

}  // namespace trajopt
