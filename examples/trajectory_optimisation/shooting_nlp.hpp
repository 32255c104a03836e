// Minimum-effort motion of the hand along the plane, as an Ipopt NLP: direct multiple shooting.
//
// Horizon T in N intervals of h = T/N. Variables, interval by interval, w_k = (q_k, q̇_k, τ_k) for
// k < N, then x_N = (q_N, q̇_N): n = 21 N + 14. Each interval is one semi-implicit Euler step of
// plane_dynamics.hpp's q̈ = f(q, q̇, τ), its defect the 14 constraints
//   c_q = q_{k+1} − q_k − h q̇_k − h² f(x_k, τ_k) = 0,   c_v = q̇_{k+1} − q̇_k − h f(x_k, τ_k) = 0,
// whose Jacobian is, with F = ∂f/∂(q, q̇, τ) (7 × 21, exact: plane_dynamics.hpp),
//   ∂c_q/∂(q_k, q̇_k, τ_k) = −[I, h I, 0] − h² F,  ∂c_v/∂(q_k, q̇_k, τ_k) = −[0, I, 0] − h F,
//   ∂c_q/∂q_{k+1} = I,  ∂c_v/∂q̇_{k+1} = I:
// 22 entries per row, 308 per interval (the sparsity stated to Ipopt). Objective: the effort
// Σ_k h Σ_i (τ_k,i / τmax_i)², plus kSpeedWeight Σ_k h ‖q̇_k‖² (without it the least effort swings
// the light wrist joints at their speed limits). Bounds: the URDF's torque, position and velocity limits; x_0 and x_N
// fixed (the start and end poses, at rest). The Hessian: Ipopt's limited-memory approximation.
#pragma once

#include <IpTNLP.hpp>

#include <vector>

#include "plane_dynamics.hpp"

namespace trajopt {

struct Problem {
  PlaneLaw law;
  double q_start[kDof];
  double q_end[kDof];
  double duration;  // T [s]
  int intervals;    // N
};

// The Panda's limits (panda.urdf).
constexpr double kTauMax[kDof] = {87, 87, 87, 87, 12, 12, 12};
constexpr double kQdMax[kDof] = {2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61};
constexpr double kQMin[kDof] = {-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973};
constexpr double kQMax[kDof] = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};

constexpr double kSpeedWeight = 0.01;  // [s²/rad²]: a joint at 1 rad/s costs a hundredth of one at its torque limit

class ShootingNlp : public Ipopt::TNLP {
 public:
  explicit ShootingNlp(const Problem& problem);

  int variables() const { return 21 * problem_.intervals + 14; }
  static int state_index(int k) { return 21 * k; }   // q_k at [state_index(k)], q̇_k after it
  static int torque_index(int k) { return 21 * k + 14; }
  const std::vector<double>& solution() const { return solution_; }
  Ipopt::SolverReturn status() const { return status_; }
  double effort() const { return effort_; }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Index nele_jac,
                  Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number* z_L,
                         const Ipopt::Number* z_U, Ipopt::Index m, const Ipopt::Number* g,
                         const Ipopt::Number* lambda, Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  Problem problem_;
  double h_;
  std::vector<double> solution_;
  Ipopt::SolverReturn status_ = Ipopt::UNASSIGNED;
  double effort_ = 0;
};

}  // namespace trajopt
