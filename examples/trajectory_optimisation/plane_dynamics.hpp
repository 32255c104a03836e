// The arm's dynamics with its hand held on the plane z = height, and their exact Jacobian.
//
// q̈ = f(q, q̇, τ) is the generated solver's (panda_plane.yaml): τ the feed-forward torque, one
// constraint direction on the hand, the plane's normal n = (0, 0, 1) in the hand's frame,
// alpha = [0; Rᵀ n], and its setpoint beta the stabilising law of the hand's height
// e = p_z − height:
//   n·p̈ = −kd ė − kp e,  so  beta = αᵀ Ẍ_hand = −kd ṗ_z − kp e − (ω × ṗ)_z + 9.81
// (Ẍ_hand is the spatial acceleration minus gravity in the hand frame, Ẍ_lin = Rᵀ p̈ − ω_b × v_b − Rᵀ g:
// sweepgen's docs/conventions.md). ν is the plane's normal force on the hand [N].
//
// The Jacobian columns (q, q̇, τ): the generated d_qdd holds q̈'s along q, q̇, τff and beta with
// alpha fixed in the hand's frame. Here alpha turns with q, and beta moves with (q, q̇). alpha enters
// the solve twice: in the constraint αᵀ Ẍ_hand = β, and as the direction of the plane's wrench α ν.
// At a fixed state, (α + δα)ᵀ Ẍ' = β + δβ is αᵀ Ẍ' = β + δβ − δαᵀ Ẍ_hand to first order, and the
// wrench's turn δα ν is a force R δn ν at the hand, the joint torques J_vᵀ R δn ν (J_v the hand's
// linear-velocity Jacobian, δα = [0; δn]). So, for x in q, q̇,
//   ∂q̈/∂x = d_qdd[x] + d_qdd[beta] (∂β/∂x − (∂α/∂x)ᵀ Ẍ_hand) + d_qdd[τff] J_vᵀ R (∂n/∂x) ν,
// and likewise for ν; ∂β/∂x, ∂n/∂x and J_v come from hand_kinematics.hpp's Dual evaluation.
#pragma once

#include "hand_kinematics.hpp"

namespace trajopt {

constexpr int kColumns = 3 * kDof;  // q, q̇, τ

struct PlaneLaw {
  double height;  // the plane's z in the base frame [m]
  double kp;      // [1/s²]
  double kd;      // [1/s]
};

struct DynamicsValue {
  double qdd[kDof];
  double nu;
  unsigned status;  // the generated solver's status (0: ok)
};
struct DynamicsJacobian : DynamicsValue {
  double d_qdd[kDof * kColumns];  // row i at [i * kColumns], columns q, q̇, τ
  double d_nu[kColumns];
};

// q̈ and ν at (q, q̇, τ): outward, decompose and solve_original.
DynamicsValue dynamics(const PlaneLaw& law, const double* q, const double* qd, const double* tau);
// q̈, ν and their Jacobians: derivatives_original, and one solve for the hand's acceleration.
DynamicsJacobian dynamics_jacobian(const PlaneLaw& law, const double* q, const double* qd, const double* tau);

// The hand's height over the plane e, its normal velocity ė = ṗ_z, and the part of ë that q̈ does
// not move, q̇ᵀ ∇²e q̇ = (∂ė/∂q) q̇ [m/s²], at (q, q̇).
void hand_height(const PlaneLaw& law, const double* q, const double* qd, double& e, double& e_dot,
                 double& e_curvature);

}  // namespace trajopt
