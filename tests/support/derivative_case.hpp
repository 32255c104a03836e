// What the derivative tests share (tests/test_solve_derivatives.cpp, tests/test_generated_derivatives.cpp):
// a bundled scene with its chain, the Jacobians of one output as one matrix, and the condition
// estimate their tolerances grow with.
#pragma once

#include <algorithm>
#include <string>

#include "oracle/condition_number.hpp"
#include "oracle/dense_dynamics.hpp"
#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "solver/solve_derivatives.hpp"
#include "support/dense_rows.hpp"

namespace sweepgen::test {

struct SceneCase {
  scene::Scene scene;
  model::Chain chain;
};

// robots/<relative>, its chain loaded.
inline SceneCase load_scene_case(const std::string& relative) {
  SceneCase c{scene::load_scene(std::string(SWEEPGEN_SOURCE_DIR) + "/robots/" + relative), {}};
  c.chain = scene::load_scene_chain(c.scene);
  return c;
}

// ∂ of one output as one matrix, columns in (D2)'s order: q, q̇, τff, β.
inline Eigen::MatrixXd stacked(const solver::Jacobians<double>& d) {
  Eigen::MatrixXd m(d.q.rows(), d.q.cols() + d.qd.cols() + d.tau_ff.cols() + d.beta.cols());
  m << d.q, d.qd, d.tau_ff, d.beta;
  return m;
}

// κ = cond_s(M) · max(1, cond_s(E^A_cstr,0)) at the state of `p`, E = J M⁻¹ Jᵀ with every set's and
// coupling's rows (test::dense_rows), from the dense oracle (long double): the condition of the
// solve (E) times that of the M⁻¹ its derivatives in q and q̇
// differentiate (‖δ(M⁻¹)‖/‖M⁻¹‖ <= cond(M) ‖δM‖/‖M‖ to first order). Both scaled
// (oracle::scaled_condition_number: cond₂ of the Jacobi-scaled matrix), so independent of the
// units of each coordinate: a floating base's kilograms against its joints' kg m² would otherwise
// count as ill-conditioning the recursion never sees.
inline double derivative_condition(const SceneCase& c, const report::Problem& p) {
  using Oracle = oracle::DenseDynamics<long double>;
  const Oracle o(c.chain, c.chain.floating_base ? model::Vec3(p.base_rotation.transpose() * c.scene.gravity)
                                                : model::Vec3(c.scene.gravity));
  const Oracle::Vec q = p.q.cast<long double>();
  const Oracle::Mat M = o.mass_matrix(q);
  double kappa = oracle::scaled_condition_number(M);
  const std::size_t nc = c.scene.layout.constraints;
  if (nc + c.chain.couplings.size() > 0) {
    Oracle::Mat alpha(6, static_cast<Eigen::Index>(nc));
    for (std::size_t k = 0; k < nc; ++k)
      alpha.col(static_cast<Eigen::Index>(k)) << p.alpha[k].moment.cast<long double>(), p.alpha[k].force.cast<long double>();
    const Oracle::Mat J = dense_rows(o, c.scene.layout, c.chain, q, Oracle::Vec(p.qd.cast<long double>()), alpha,
                                     Oracle::Vec::Zero(static_cast<Eigen::Index>(nc))).Jc;
    kappa *= std::max(1.0, oracle::scaled_condition_number(Oracle::constraint_energy(M, J)));
  }
  return kappa;
}

}  // namespace sweepgen::test
