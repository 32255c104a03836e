#include "support/inputs.hpp"

#include <cmath>
#include <stdexcept>

namespace sweepgen::bench {

void Random::unit_direction(std::vector<double>& out) {
  double v[6], norm = 0;
  for (double& x : v) {
    x = uniform(-1, 1);
    norm += x * x;
  }
  norm = std::sqrt(norm);
  for (double x : v) out.push_back(x / norm);
}

SceneInputs make_inputs(const std::string& scene_path, std::size_t count, unsigned seed) {
  SceneInputs s;
  s.scene = scene::load_scene(scene_path);
  s.chain = scene::load_scene_chain(s.scene);
  s.dof = s.chain.dof();
  s.constraints = s.scene.layout.constraints;
  const bool runtime_directions = s.scene.fixed_directions.empty();
  Random random(seed);
  for (std::size_t state = 0; state < count; ++state) {
    std::vector<double> in;
    for (std::size_t i = 1; i <= s.dof; ++i) {
      const auto& j = s.chain.joints[i];
      in.push_back(random.uniform(std::isfinite(j.lower) ? j.lower : -M_PI, std::isfinite(j.upper) ? j.upper : M_PI));
    }
    for (std::size_t i = 0; i < s.dof; ++i) in.push_back(random.uniform(-2, 2));
    for (std::size_t t = 0; t < s.scene.layout.torques.size(); ++t) {
      const double fraction = t == 0 ? 1.5 : 0.2;
      for (std::size_t i = 1; i <= s.dof; ++i) {
        const double e = s.chain.joints[i].effort_limit;
        const double limit = std::isfinite(e) && e > 0 ? e : 10.0;
        in.push_back(random.uniform(-fraction * limit, fraction * limit));
      }
    }
    for (std::size_t e = 0; e < s.scene.layout.external_forces.size(); ++e) {
      for (int k = 0; k < 3; ++k) in.push_back(random.uniform(-2, 2));
      for (int k = 0; k < 3; ++k) in.push_back(random.uniform(-20, 20));
    }
    if (runtime_directions)
      for (std::size_t k = 0; k < s.constraints; ++k) random.unit_direction(in);
    for (std::size_t k = 0; k < s.constraints; ++k) in.push_back(random.uniform(-3, 3));
    std::vector<double> beta;
    for (std::size_t k = 0; k < s.constraints; ++k) beta.push_back(random.uniform(-3, 3));
    s.flat.push_back(std::move(in));
    s.new_beta.push_back(std::move(beta));
  }
  return s;
}

std::vector<ReferenceInput> reference_inputs(const SceneInputs& s) {
  std::vector<ReferenceInput> result;
  const std::size_t n = s.dof, nc = s.constraints;
  for (const auto& in : s.flat) {
    ReferenceInput r;
    r.drivers = solver::DriverInputs<double>::sized(s.scene.layout, n);
    std::size_t at = 0;
    const auto take = [&](std::size_t count) {
      if (at + count > in.size()) throw std::logic_error("flat input too short");
      const double* p = in.data() + at;
      at += count;
      return p;
    };
    r.q = Eigen::Map<const Eigen::VectorXd>(take(n), static_cast<Eigen::Index>(n));
    r.qd = Eigen::Map<const Eigen::VectorXd>(take(n), static_cast<Eigen::Index>(n));
    for (auto& tau : r.drivers.torques) tau = Eigen::Map<const Eigen::VectorXd>(take(n), static_cast<Eigen::Index>(n));
    for (auto& w : r.drivers.external_forces) {
      const double* p = take(6);
      w.moment = Eigen::Vector3d(p[0], p[1], p[2]);
      w.force = Eigen::Vector3d(p[3], p[4], p[5]);
    }
    for (std::size_t k = 0; k < nc; ++k) {
      if (s.scene.fixed_directions.empty()) {
        const double* p = take(6);
        r.drivers.constraint_directions[k].moment = Eigen::Vector3d(p[0], p[1], p[2]);
        r.drivers.constraint_directions[k].force = Eigen::Vector3d(p[3], p[4], p[5]);
      } else {
        r.drivers.constraint_directions[k] = s.scene.fixed_directions[k];
      }
    }
    r.beta = Eigen::Map<const Eigen::VectorXd>(take(nc), static_cast<Eigen::Index>(nc));
    if (at != in.size()) throw std::logic_error("flat input too long");
    result.push_back(std::move(r));
  }
  return result;
}

}  // namespace sweepgen::bench
