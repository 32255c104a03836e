// The Jacobians of the solve's residuals along q and q̇ (docs/derivation.md, (D8)), in closed
// form: what (D5) multiplies by the τff and β columns. With the solution (q̈, ν) held,
//   ρ_j = τff_j − d_j q̈_j − S_jᵀ F_j,   F_j = Σ_{i in j's subtree} f_i,
//   f_i = M_i Ẍ_i + Ẋ_i ×* M_i Ẋ_i − (the external and constraint wrenches on body i)   (T1 − T2)
//   r_k = E_cstr,k − α_kᵀ Ẍ_link(k)                                                      (R1)
// Everything is taken to coordinates c that no column moves (frame 0, the base's, or body 1's
// frame where body 1 carries every body: the derivatives of a frame's own motion do not appear),
// where moving q_m turns the subtree it carries about S_m. That turn cancels in every
// power pairing inside the subtree, so what is left is, per joint, a few 6-vectors built from the
// subtree's composite inertia Y, Coriolis composite Q and momentum H, and per pair of joints a
// dot product or two: no tangent of the kinematics is propagated.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "solver/decomposition_sweep.hpp"
#include "solver/joint_couplings.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// Σ_{i in the subtree} (M_i [Ẋ_i×] + [Ẋ_i×]ᵀ M_i) in the coordinates c, the symmetric part of what the
// bodies' velocity products add along a change of velocity (D8): [T  s×; (s×)ᵀ  0], per body
// T = Ī [ω×] − [ω×] Ī + u hᵀ + h uᵀ − 2 (h·u) 1 and s = h × ω − m u for Ẋ = [ω; u].
template <class Scalar>
struct CoriolisComposite {
  Mat3<Scalar> T = Mat3<Scalar>::Zero();
  Vec3<Scalar> s = Vec3<Scalar>::Zero();

  static CoriolisComposite of(const Inertia<Scalar>& M, const Motion<Scalar>& v) {
    const Vec3<Scalar> h(M.B(2, 1), M.B(0, 2), M.B(1, 0));  // B = h×
    const Scalar& m = M.C(0, 0);
    const Mat3<Scalar> A_w = M.A * spatial::skew(v.angular);
    CoriolisComposite q;
    q.T = A_w + A_w.transpose() + v.linear * h.transpose() + h * v.linear.transpose() -
          Mat3<Scalar>::Identity() * (Scalar(2) * h.dot(v.linear));
    spatial::symmetrize_from_upper(q.T);
    q.s = h.cross(v.angular) - v.linear * m;
    return q;
  }
  CoriolisComposite operator+(const CoriolisComposite& o) const { return {T + o.T, s + o.s}; }
  Force<Scalar> operator*(const Motion<Scalar>& x) const {
    return {T * x.angular + s.cross(x.linear), -s.cross(x.angular)};
  }
};

// (D8)'s quantities, every one readable after the sweep: per body i (0..N) in the coordinates c,
// then the residuals' Jacobians.
template <class Scalar>
struct ResidualJacobians {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  std::vector<Transform<Scalar>> to_body;            // ^iX_c
  std::vector<Motion<Scalar>> axis, axis_rate;       // S_i, Ṡ_i = Ẋ_P × S_i
  std::vector<Motion<Scalar>> velocity, acceleration;  // Ẋ_i, Ẍ_i
  std::vector<Inertia<Scalar>> composite_inertia;    // Y_i = Σ_{subtree} M
  std::vector<CoriolisComposite<Scalar>> composite_coriolis;  // Q_i
  std::vector<Force<Scalar>> composite_momentum, composite_force;  // H_i = Σ M Ẋ, F_i = Σ f
  std::vector<Motion<Scalar>> acceleration_along_q, acceleration_along_qd;  // a_i, ψ_i (joint i)
  std::vector<Force<Scalar>> inertia_on_axis, coriolis_on_axis;  // g_i, k_i (joint i's rows)
  std::vector<Force<Scalar>> force_along_q, force_along_qd;      // U_i, V_i (joint i's column)
  // ∂ρ/∂q, ∂ρ/∂q̇ (N × N): rows the joints' residuals, columns the joints (a coupled one's 0: its
  // source's holds it)
  Matrix rho_q, rho_qd;
  Matrix r_q, r_qd;      // ∂r/∂q, ∂r/∂q̇ (Nc × N)
};

// (D8). @pre kin: the outward sweep of the state's values, qd its q̇; held: the solution's q̈ and
// ν (values; nothing else of it is read); inputs: the external forces and the directions α.
template <class Scalar>
ResidualJacobians<Scalar> residual_jacobians(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                             const JointVector<Scalar>& qd, const DriverInputs<Scalar>& inputs,
                                             const Solution<Scalar>& held) {
  using spatial::cross_force;
  using spatial::cross_motion;
  using spatial::dot;
  const std::size_t n = model.dof(), nc = model.constraints(), base = model.base_coordinates();
  // A joint's group: a floating base's six coordinates are one free joint on body 0 that carries
  // the root link (body `base`, F5); every other joint is its own, on its parent.
  const auto group_parent = [&](std::size_t m) { return m <= base ? std::size_t(0) : model.parent[m]; };
  const auto group_body = [&](std::size_t m) { return m <= base ? base : m; };
  const auto carries = [&](std::size_t a, std::size_t c) { return model::supports(model.parent, a, c); };
  // The coordinates c: body 1's frame where body 1 carries every other body (M_1 and S_1 are
  // constants there, and a joint about the gravity's axis costs nothing), else frame 0. Any frame
  // that no column moves would do; body 1's moves with q_1 only, and q_1's column is taken at the
  // present q_1, where ^1X_0 is a fixed isometry (it keeps every product below).
  bool body_1_carries_all = n >= 1;
  for (std::size_t i = 2; i <= n; ++i) body_1_carries_all = body_1_carries_all && model.parent[i] != 0;

  ResidualJacobians<Scalar> J;
  for (auto* motions : {&J.axis, &J.axis_rate, &J.velocity, &J.acceleration, &J.acceleration_along_q, &J.acceleration_along_qd})
    motions->assign(n + 1, Motion<Scalar>{});
  for (auto* forces : {&J.composite_momentum, &J.composite_force, &J.inertia_on_axis, &J.coriolis_on_axis,
                       &J.force_along_q, &J.force_along_qd})
    forces->assign(n + 1, Force<Scalar>{});
  J.to_body.assign(n + 1, Transform<Scalar>::identity());
  J.composite_inertia.assign(n + 1, Inertia<Scalar>{});
  J.composite_coriolis.assign(n + 1, CoriolisComposite<Scalar>{});
  auto& X = J.to_body;
  auto &S = J.axis, &S_dot = J.axis_rate, &v = J.velocity, &a = J.acceleration;
  auto& Y = J.composite_inertia;
  auto& Q = J.composite_coriolis;
  auto &H = J.composite_momentum, &F = J.composite_force;

  // Base to tip: ^iX_c, S_i, Ẋ_i, Ṡ_i, Ẍ_i, and the body's own M_i, Q_i, h_i = M_i Ẋ_i and
  // f_i = M_i Ẍ_i + Ẋ_i ×* h_i − (the external and constraint wrenches on it).
  a[0] = body_1_carries_all ? kin.body[1].X.apply(kin.base_acceleration) : kin.base_acceleration;
  for (std::size_t i = 1; i <= n; ++i) {
    const std::size_t p = model.parent[i];
    if (!(i == 1 && body_1_carries_all)) X[i] = kin.body[i].X * X[p];
    S[i] = X[i].apply_inverse(model.joints[i].S);
    const Scalar qd_i = joint_velocity(model, qd, i);  // a coupled joint's from its source's (M1)
    v[i] = v[p] + S[i] * qd_i;
    if (i > base) S_dot[i] = cross_motion(v[group_parent(i)], S[i]);  // 0 for the free joint (F5)
    a[i] = a[p] + S[i] * held.qdd[i - 1] + S_dot[i] * qd_i;
    Y[i] = model.inertia[i].rigid_transformed_to_parent(X[i]);
    H[i] = Y[i] * v[i];
    Q[i] = CoriolisComposite<Scalar>::of(Y[i], v[i]);
    F[i] = Y[i] * a[i] + cross_force(v[i], H[i]);
    Force<Scalar> applied;  // in body i's frame
    for (std::size_t e = 0; e < model.external_force_body.size(); ++e) applied += external_own_force(model, inputs, e, i);
    for (std::size_t k = 0; k < nc; ++k) applied += constraint_own_force(model, kin, inputs, k, i) * held.nu[k];
    F[i] -= X[i].apply_transpose(applied);
  }
  // Tip to base: the subtrees' composites.
  for (std::size_t i = n; i > 1; --i) {
    const std::size_t p = model.parent[i];
    if (p == 0) continue;
    Y[p] = Y[p] + Y[i];
    Q[p] = Q[p] + Q[i];
    H[p] += H[i];
    F[p] += F[i];
  }

  // Per joint m (its group's body G and parent P): Ẍ past it moves along q_m by the turn S_m × Ẍ
  // and Ṡ_m × Ẋ + a_m, a_m = Ẍ_P × S_m + Ẋ_P × Ṡ_m; along q̇_m by S_m × Ẋ + ψ_m,
  // ψ_m = (Ẋ_P + Ẋ_G) × S_m (2 Ṡ_m for a joint of one coordinate). The 6-vectors the pairs read:
  // g_m = Y_G S_m, k_m = Q_G S_m + S_m ×* H_G (joint m's row), U_m, V_m (its column, in the rows
  // of the joints that carry it).
  auto &dAdq = J.acceleration_along_q, &psi = J.acceleration_along_qd;
  auto &g = J.inertia_on_axis, &k = J.coriolis_on_axis, &U = J.force_along_q, &V = J.force_along_qd;
  for (std::size_t m = 1; m <= n; ++m) {
    const std::size_t P = group_parent(m), G = group_body(m);
    dAdq[m] = cross_motion(a[P], S[m]) + cross_motion(v[P], S_dot[m]);
    psi[m] = m <= base ? cross_motion(v[P] + v[G], S[m]) : S_dot[m] * Scalar(2);
    const Force<Scalar> S_H = cross_force(S[m], H[G]);
    const Force<Scalar> QS = Q[G] * S[m];
    g[m] = Y[G] * S[m];
    k[m] = QS + S_H;
    U[m] = cross_force(S[m], F[G]) + Y[G] * dAdq[m] - Q[G] * S_dot[m] + cross_force(S_dot[m], H[G]);
    V[m] = Y[G] * psi[m] - QS + S_H;
  }

  // Each constraint set's frame A from the coordinates c, ^A X_c, where its α_k are given; and for a set
  // between two links, the wrench its multipliers put on the other link, w = (^A X_c)ᵀ Σ α_k ν_k in c
  // (what F holds of it at body b: L4), which is fixed in A, not in b.
  std::vector<Transform<Scalar>> to_link;
  std::vector<Force<Scalar>> other_wrench;
  for (const ConstraintSetModel<Scalar>& set : model.constraint_sets) {
    to_link.push_back(set.frame * X[set.body]);
    Force<Scalar> alpha_nu;
    for (std::size_t k = set.first; set.relative && k < set.first + set.count; ++k)
      alpha_nu += inputs.constraint_directions[k] * held.nu[k];
    other_wrench.push_back(to_link.back().apply_transpose(alpha_nu));
  }

  J.rho_q.setZero(n, n);
  J.rho_qd.setZero(n, n);
  J.r_q.setZero(nc, n);
  J.r_qd.setZero(nc, n);
  const auto index = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
  for (std::size_t m = 1; m <= n; ++m) {
    // A floating base's q columns are its rotation vector's three (its position's are 0: nothing reads it).
    const bool q_column = m > base || m <= 3;
    // ρ_j = τff_j − d_j q̈_j − S_jᵀ F_j
    for (std::size_t j = 1; j <= n; ++j) {
      Scalar d_q(0), d_qd(0);
      bool related = true;
      if (carries(group_body(m), group_body(j))) {  // S_j turns with q_m: the turn cancels in S_jᵀ F_j
        d_q = dot(g[j], dAdq[m]) - dot(k[j], S_dot[m]);
        d_qd = dot(g[j], psi[m]) - dot(k[j], S[m]);
      } else if (carries(group_body(j), group_body(m))) {  // j carries m: S_j stays
        d_q = dot(U[m], S[j]);
        d_qd = dot(V[m], S[j]);
      } else {
        related = false;
      }
      // A set between two links puts w on its other link b, fixed in A: it turns with q_m where m's
      // group carries a, where the sums above turned it where m's group carries b (L4).
      for (std::size_t c = 0; c < model.constraint_sets.size(); ++c) {
        const ConstraintSetModel<Scalar>& set = model.constraint_sets[c];
        if (!set.relative || set.other_body == 0 || !carries(group_body(j), set.other_body)) continue;
        const bool turns = carries(group_body(m), set.body), turned = carries(group_body(m), set.other_body);
        if (turns == turned) continue;
        const Scalar share = dot(cross_force(S[m], other_wrench[c]), S[j]);
        d_q += turns ? share : -share;
        related = true;
      }
      if (!related) continue;
      if (q_column) J.rho_q(index(j - 1), index(m - 1)) = -d_q;
      J.rho_qd(index(j - 1), index(m - 1)) = -d_qd;
    }
    // r_k = E_cstr,k − α_kᵀ Ẍ_link: Ẍ_b moves past q_m by its turn, which α_k's cancels, and by
    // Ṡ_m × Ẋ_b + a_m; along q̇_m by S_m × Ẋ_b + ψ_m: taken to the set's link frame.
    // A set between links a and b reads α_kᵀ ^AX_c Z, Z = Ẍ_a − Ẍ_b + Ẋ_a × Ẋ_b (L1 in c); where m's
    // group carries both, Z turns with the row (the Jacobi identity): nothing moves; where it carries
    // one of them, what is left of ∂Z beyond the row's turn (δ_a S_m × Z) is below.
    for (std::size_t c = 0; c < model.constraint_sets.size(); ++c) {
      const ConstraintSetModel<Scalar>& set = model.constraint_sets[c];
      const bool carries_a = carries(group_body(m), set.body);
      const bool carries_b = set.relative && set.other_body != 0 && carries(group_body(m), set.other_body);
      if (carries_a == carries_b) continue;
      Motion<Scalar> along_q, along_qd;
      if (!set.relative) {
        along_q = dAdq[m] + cross_motion(S_dot[m], v[set.body]);
        along_qd = cross_motion(S[m], v[set.body]) + psi[m];
      } else {
        const Motion<Scalar>&va = v[set.body], &vb = v[set.other_body], &ab = a[set.other_body];
        const Motion<Scalar> S_vb = cross_motion(S[m], vb);
        if (carries_a) {  // a_m + S_m × Ẍ_b − Ẋ_a × (S_m × Ẋ_b) + Ṡ_m × (Ẋ_a + Ẋ_b);  ψ_m + S_m × (Ẋ_a + Ẋ_b)
          along_q = dAdq[m] + cross_motion(S[m], ab) - cross_motion(va, S_vb) + cross_motion(S_dot[m], va + vb);
          along_qd = psi[m] + cross_motion(S[m], va + vb);
        } else {  // −(a_m + S_m × Ẍ_b + Ṡ_m × Ẋ_b) + Ẋ_a × (S_m × Ẋ_b + Ṡ_m);  −ψ_m − S_m × (Ẋ_a + Ẋ_b)
          along_q = cross_motion(va, S_vb + S_dot[m]) - dAdq[m] - cross_motion(S[m], ab) - cross_motion(S_dot[m], vb);
          along_qd = Motion<Scalar>{} - psi[m] - cross_motion(S[m], va + vb);
        }
      }
      along_q = to_link[c].apply(along_q);
      along_qd = to_link[c].apply(along_qd);
      for (std::size_t k = set.first; k < set.first + set.count; ++k) {
        if (q_column) J.r_q(index(k), index(m - 1)) = -dot(inputs.constraint_directions[k], along_q);
        J.r_qd(index(k), index(m - 1)) = -dot(inputs.constraint_directions[k], along_qd);
      }
    }
  }
  // A coupled joint's q and q̇ follow its source's (M1): its columns join the source's, times the
  // multiplier, and are no columns of their own (the chain rule; a coupling's row of r has no q, q̇).
  for (const JointCouplingModel<Scalar>& coupling : model.couplings)
    for (auto* columns : {&J.rho_q, &J.rho_qd, &J.r_q, &J.r_qd}) {
      for (Eigen::Index row = 0; row < columns->rows(); ++row) {
        Scalar& joint = (*columns)(row, index(coupling.joint - 1));
        (*columns)(row, index(coupling.source - 1)) += coupling.multiplier * joint;
        joint = Scalar(0);
      }
    }
  return J;
}

}  // namespace sweepgen::solver
