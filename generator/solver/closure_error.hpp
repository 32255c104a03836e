// The closure error of a set between two links (docs/derivation.md, (L3)): how far frame A is from
// frame B, [the rotation vector of R_B^T R_A, angle in [0, π]; R_A^T (p_A − p_B)], from ᴬX_B =
// (E, r) = (R_A^T R_B, R_B^T (p_A − p_B)): R_B^T R_A = E^T and R_A^T (p_A − p_B) = E r. With v_rel
// (L1) it is what an application's stabilising setpoints read, β = −Kd α^T v_rel − Kp α^T e.
//
// The rotation vector θ a of R, branch-free (both forms computed, one selected):
//   w = vee(R − R^T) = 2 sin θ a,  cos θ = (tr R − 1) / 2,  θ = atan2(|w| / 2, cos θ)
//   cos θ > −1/2:  θ a = θ / (2 sin θ) w   (θ / sin θ → 1 as θ → 0: 1/2 w where |w| / 2 ≤ 1e-8, exact
//                  to the double's rounding there since θ / sin θ = 1 + θ² / 6)
//   cos θ ≤ −1/2:  (R + R^T) / 2 − cos θ 1 = (1 − cos θ) a a^T: a from its column j of largest diagonal,
//                  a = column_j / sqrt((1 − cos θ) B_jj), its sign that of a^T w (w = 2 sin θ a)
// The first form loses accuracy as sin θ → 0 near π (a from w / sin θ); the second near 0 (B → 0).
#pragma once

#include "solver/outward_sweep.hpp"
#include "solver/scalar_ops.hpp"

namespace sweepgen::solver {

template <class Scalar>
spatial::Vec3<Scalar> rotation_vector(const spatial::Mat3<Scalar>& R) {
  using std::atan2;
  using std::sqrt;
  const spatial::Vec3<Scalar> w(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const Scalar cosine = (R(0, 0) + R(1, 1) + R(2, 2) - Scalar(1)) / Scalar(2);
  const Scalar sine = sqrt(w.dot(w)) / Scalar(2);
  const Scalar angle = atan2(sine, cosine);
  const Scalar half_ratio = select_greater(sine, Scalar(1e-8), angle / (sine + sine), Scalar(0.5));
  const spatial::Vec3<Scalar> from_w = w * half_ratio;
  // Near π: the column of B = (R + R^T) / 2 − cos θ 1 with the largest diagonal.
  spatial::Mat3<Scalar> B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) B(i, j) = (R(i, j) + R(j, i)) / Scalar(2) - (i == j ? cosine : Scalar(0));
  spatial::Vec3<Scalar> column = B.col(0);
  Scalar diagonal = B(0, 0);
  for (int j = 1; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) column[i] = select_greater(B(j, j), diagonal, B(i, j), column[i]);
    diagonal = select_greater(B(j, j), diagonal, B(j, j), diagonal);
  }
  const spatial::Vec3<Scalar> axis = column / sqrt((Scalar(1) - cosine) * diagonal);
  const Scalar sign = select_greater(Scalar(0), axis.dot(w), Scalar(-1), Scalar(1));
  const spatial::Vec3<Scalar> near_pi = axis * (sign * angle);
  spatial::Vec3<Scalar> v;
  for (int i = 0; i < 3; ++i) v[i] = select_greater(cosine, Scalar(-0.5), from_w[i], near_pi[i]);
  return v;
}

// (L3) of set s between two links, from the outward sweep: [rotation vector of R_B^T R_A; R_A^T (p_A − p_B)].
template <class Scalar>
spatial::Motion<Scalar> pose_error(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin, std::size_t s) {
  const Transform<Scalar> A_X_B = relative_pose(model, kin, s);
  return {rotation_vector(spatial::Mat3<Scalar>(A_X_B.E.transpose())), A_X_B.E * A_X_B.r};
}

// Per set between two links, in set order: [pose error (L3); v_rel (L1)], twelve numbers.
template <class Scalar>
void closure_errors(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                    std::vector<std::array<spatial::Motion<Scalar>, 2>>& out) {
  out.clear();  // no allocation where sized so (Solution::sized)
  for (std::size_t s = 0; s < model.constraint_sets.size(); ++s)
    if (model.constraint_sets[s].relative) out.push_back({pose_error(model, kin, s), kin.loop[s].relative_velocity});
}

}  // namespace sweepgen::solver
