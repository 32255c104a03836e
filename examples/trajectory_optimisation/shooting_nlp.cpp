// shooting_nlp.hpp: the multiple-shooting NLP and its exact constraint Jacobian.
#include "shooting_nlp.hpp"

namespace trajopt {

using Ipopt::Index;
using Ipopt::Number;

namespace {
constexpr int kRowsPerInterval = 2 * kDof;
constexpr int kEntriesPerRow = kColumns + 1;  // (q_k, q̇_k, τ_k) and one of x_{k+1}
}  // namespace

ShootingNlp::ShootingNlp(const Problem& problem)
    : problem_(problem), h_(problem.duration / problem.intervals) {}

bool ShootingNlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) {
  n = variables();
  m = kRowsPerInterval * problem_.intervals;
  nnz_jac_g = m * kEntriesPerRow;
  nnz_h_lag = 0;  // hessian_approximation limited-memory
  index_style = C_STYLE;
  return true;
}

bool ShootingNlp::get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) {
  const int N = problem_.intervals;
  for (int k = 0; k <= N; ++k) {
    const int s = state_index(k);
    for (int i = 0; i < kDof; ++i) {
      x_l[s + i] = kQMin[i];
      x_u[s + i] = kQMax[i];
      x_l[s + kDof + i] = -kQdMax[i];
      x_u[s + kDof + i] = kQdMax[i];
      if (k < N) {
        x_l[torque_index(k) + i] = -kTauMax[i];
        x_u[torque_index(k) + i] = kTauMax[i];
      }
    }
  }
  for (int i = 0; i < kDof; ++i) {  // the start and end poses, at rest: fixed variables
    x_l[i] = x_u[i] = problem_.q_start[i];
    x_l[kDof + i] = x_u[kDof + i] = 0;
    x_l[state_index(N) + i] = x_u[state_index(N) + i] = problem_.q_end[i];
    x_l[state_index(N) + kDof + i] = x_u[state_index(N) + kDof + i] = 0;
  }
  for (int r = 0; r < m; ++r) g_l[r] = g_u[r] = 0;
  (void)n;
  return true;
}

// The joints move linearly from start to end at constant speed, no torque: a guess off the plane
// and off the dynamics, which the defects pull onto both.
bool ShootingNlp::get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                                     bool init_lambda, Number*) {
  if (!init_x || init_z || init_lambda) return false;
  const int N = problem_.intervals;
  for (int k = 0; k <= N; ++k) {
    const double s = static_cast<double>(k) / N;
    for (int i = 0; i < kDof; ++i) {
      const double dq = problem_.q_end[i] - problem_.q_start[i];
      x[state_index(k) + i] = problem_.q_start[i] + s * dq;
      x[state_index(k) + kDof + i] = (k == 0 || k == N) ? 0 : dq / problem_.duration;
      if (k < N) x[torque_index(k) + i] = 0;
    }
  }
  (void)n;
  return true;
}

bool ShootingNlp::eval_f(Index, const Number* x, bool, Number& obj_value) {
  obj_value = 0;
  for (int k = 0; k < problem_.intervals; ++k)
    for (int i = 0; i < kDof; ++i) {
      const double t = x[torque_index(k) + i] / kTauMax[i];
      const double v = x[state_index(k) + kDof + i];
      obj_value += h_ * (t * t + kSpeedWeight * v * v);
    }
  return true;
}

bool ShootingNlp::eval_grad_f(Index n, const Number* x, bool, Number* grad_f) {
  for (int j = 0; j < n; ++j) grad_f[j] = 0;
  for (int k = 0; k < problem_.intervals; ++k)
    for (int i = 0; i < kDof; ++i) {
      grad_f[torque_index(k) + i] = 2 * h_ * x[torque_index(k) + i] / (kTauMax[i] * kTauMax[i]);
      grad_f[state_index(k) + kDof + i] = 2 * h_ * kSpeedWeight * x[state_index(k) + kDof + i];
    }
  return true;
}

bool ShootingNlp::eval_g(Index, const Number* x, bool, Index, Number* g) {
  for (int k = 0; k < problem_.intervals; ++k) {
    const double* q = x + state_index(k);
    const double* qd = q + kDof;
    const double* q_next = x + state_index(k + 1);
    const double* qd_next = q_next + kDof;
    const DynamicsValue f = dynamics(problem_.law, q, qd, x + torque_index(k));
    if (f.status != 0) return false;  // a dropped direction: Ipopt cuts the step back
    double* c = g + kRowsPerInterval * k;
    for (int i = 0; i < kDof; ++i) {
      c[i] = q_next[i] - q[i] - h_ * qd[i] - h_ * h_ * f.qdd[i];
      c[kDof + i] = qd_next[i] - qd[i] - h_ * f.qdd[i];
    }
  }
  return true;
}

bool ShootingNlp::eval_jac_g(Index, const Number* x, bool, Index, Index nele_jac, Index* iRow, Index* jCol,
                             Number* values) {
  if (values == nullptr) {  // the structure: per row, (q_k, q̇_k, τ_k) then its entry of x_{k+1}
    Index e = 0;
    for (int k = 0; k < problem_.intervals; ++k)
      for (int r = 0; r < kRowsPerInterval; ++r) {
        for (int c = 0; c < kColumns; ++c, ++e) {
          iRow[e] = kRowsPerInterval * k + r;
          jCol[e] = state_index(k) + c;
        }
        iRow[e] = kRowsPerInterval * k + r;
        jCol[e] = state_index(k + 1) + r;  // q_{k+1,r} for c_q, q̇_{k+1,r-7} for c_v
        ++e;
      }
    return e == nele_jac;
  }
  const double h = h_;
  for (int k = 0; k < problem_.intervals; ++k) {
    const double* q = x + state_index(k);
    const DynamicsJacobian f = dynamics_jacobian(problem_.law, q, q + kDof, x + torque_index(k));
    if (f.status != 0) return false;
    Number* v = values + kRowsPerInterval * kEntriesPerRow * k;
    for (int i = 0; i < kDof; ++i) {
      Number* row_q = v + i * kEntriesPerRow;
      Number* row_v = v + (kDof + i) * kEntriesPerRow;
      const double* F = f.d_qdd + i * kColumns;
      for (int c = 0; c < kColumns; ++c) {
        row_q[c] = -h * h * F[c];
        row_v[c] = -h * F[c];
      }
      row_q[i] -= 1;            // −I along q_k
      row_q[kDof + i] -= h;     // −h I along q̇_k
      row_v[kDof + i] -= 1;     // −I along q̇_k
      row_q[kColumns] = 1;      // q_{k+1}
      row_v[kColumns] = 1;      // q̇_{k+1}
    }
  }
  return true;
}

void ShootingNlp::finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*,
                                    const Number*, Index, const Number*, const Number*, Number obj_value,
                                    const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  status_ = status;
  solution_.assign(x, x + n);
  effort_ = obj_value;
}

}  // namespace trajopt
