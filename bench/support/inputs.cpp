#include "support/inputs.hpp"

#include <cmath>

namespace sweepgen::bench {

spatial::Force<double> Random::unit_direction() {
  double v[6], norm = 0;
  for (double& x : v) {
    x = uniform(-1, 1);
    norm += x * x;
  }
  norm = std::sqrt(norm);
  return {Eigen::Vector3d(v[0], v[1], v[2]) / norm, Eigen::Vector3d(v[3], v[4], v[5]) / norm};
}

SceneInputs make_inputs(const std::string& scene_path, std::size_t count, unsigned seed) {
  SceneInputs s;
  s.scene = scene::load_scene(scene_path);
  s.chain = scene::load_scene_chain(s.scene);
  s.dof = s.chain.dof();
  s.constraints = s.scene.layout.constraints;
  const solver::FlatLayout layout = s.scene.flat_layout(s.chain);
  const auto n = static_cast<Eigen::Index>(s.dof);
  Random random(seed);
  for (std::size_t state = 0; state < count; ++state) {
    solver::SolveInputs<double> p;
    p.q.resize(n);
    p.qd.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto& j = s.chain.joints[static_cast<std::size_t>(i) + 1];
      p.q[i] = random.uniform(std::isfinite(j.lower) ? j.lower : -M_PI, std::isfinite(j.upper) ? j.upper : M_PI);
    }
    for (Eigen::Index i = 0; i < n; ++i) p.qd[i] = random.uniform(-2, 2);
    for (std::size_t t = 0; t < s.scene.layout.torques.size(); ++t) {
      const double fraction = t == 0 ? 1.5 : 0.2;
      Eigen::VectorXd tau(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        const double e = s.chain.joints[static_cast<std::size_t>(i) + 1].effort_limit;
        const double limit = std::isfinite(e) && e > 0 ? e : 10.0;
        tau[i] = random.uniform(-fraction * limit, fraction * limit);
      }
      p.torques.push_back(tau);
    }
    for (std::size_t e = 0; e < s.scene.layout.external_forces.size(); ++e) {
      spatial::Force<double> w;
      for (int k = 0; k < 3; ++k) w.moment[k] = random.uniform(-2, 2);
      for (int k = 0; k < 3; ++k) w.force[k] = random.uniform(-20, 20);
      p.wrenches.push_back(w);
    }
    p.alpha = solver::directions_with(s.scene.layout, [&random] { return random.unit_direction(); });
    p.beta.resize(static_cast<Eigen::Index>(s.constraints));
    for (auto& b : p.beta) b = random.uniform(-3, 3);
    std::vector<double> beta;
    for (std::size_t k = 0; k < s.constraints; ++k) beta.push_back(random.uniform(-3, 3));
    s.flat.push_back(solver::flat_input(p, layout));
    s.problems.push_back(std::move(p));
    s.new_beta.push_back(std::move(beta));
  }
  return s;
}

}  // namespace sweepgen::bench
