#include "report/extreme_states.hpp"

#include <cmath>
#include <random>

namespace sweepgen::report {
namespace {

// Our own mapping of mt19937_64's fixed sequence (the standard's distributions vary by library).
class Uniform {
 public:
  explicit Uniform(unsigned long long seed) : rng_(seed) {}
  double operator()(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1p-53); }
  double sign() { return (*this)(0, 1) < 0.5 ? -1.0 : 1.0; }

 private:
  std::mt19937_64 rng_;
};

spatial::Force<double> unit(const spatial::Force<double>& f) {
  return f * (1.0 / std::sqrt(f.moment.squaredNorm() + f.force.squaredNorm()));
}

}  // namespace

double length_scale(const model::Chain& chain) {
  double sum = 0;
  for (std::size_t i = 1; i <= chain.dof(); ++i) sum += chain.joints[i].tree_transform.r.norm();
  return sum > 0 ? sum / static_cast<double>(chain.dof()) : 1.0;
}

std::vector<LabelledProblem> extreme_states(const scene::Scene& s, const model::Chain& chain, std::size_t per_kind,
                                            const std::vector<double>& singular_q, unsigned long long seed) {
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  // The redundant and axis-aligned families rewrite α within one set of run-time directions.
  const auto sets = s.layout.constraint_sets();
  const bool run_time_alpha = sets.size() == 1 && !sets.front().directions_fixed();
  const double length = length_scale(chain);
  Uniform uniform(seed ^ 0x5eed);
  std::vector<LabelledProblem> states;
  const auto add = [&](const std::string& kind, Problem p, double delta = 0) {
    pack_flat(s, chain, p);
    states.push_back({kind, delta, std::move(p)});
  };
  const auto base = [&](unsigned long long offset) { return random_problems(s, chain, per_kind, seed + offset); };

  for (Problem& p : base(0)) add("nominal", p);
  for (Problem& p : base(1)) {
    for (std::size_t i = 1; i <= n; ++i)
      p.qd[static_cast<Eigen::Index>(i - 1)] =
          uniform.sign() * 100 * (chain.joints[i].type == model::JointType::prismatic ? length : 1.0);
    add("fast", p);
  }
  for (Problem& p : base(2)) {
    for (auto& w : p.wrenches)
      for (int k = 0; k < 3; ++k) {
        w.force[k] = uniform(-1e6, 1e6);
        w.moment[k] = uniform(-1e6, 1e6) * length;
      }
    add("huge_force", p);
  }
  if (run_time_alpha && nc >= 3) {
    for (Problem& p : base(3)) {
      p.alpha[1] = p.alpha[0];                            // a repeated direction
      p.alpha[2] = unit(p.alpha[0] + p.alpha[nc - 1]);    // a linear combination of two others
      add("redundant", p);
    }
  }
  if (!singular_q.empty() && singular_q.size() == n) {
    const std::vector<Problem> near = base(4);
    const double deltas[] = {0, 1e-2, 1e-4, 1e-6, 1e-8, 1e-10};
    for (std::size_t d = 0; d < std::size(deltas); ++d)
      for (std::size_t k = 0; k < near.size(); ++k) {
        Problem p = near[k];
        for (std::size_t i = 0; i < n; ++i) p.q[static_cast<Eigen::Index>(i)] = singular_q[i] + deltas[d] * uniform(-1, 1);
        if (run_time_alpha && nc == 6)
          for (std::size_t c = 0; c < 6; ++c) {
            p.alpha[c] = spatial::Force<double>{};
            (c < 3 ? p.alpha[c].moment : p.alpha[c].force)[static_cast<Eigen::Index>(c % 3)] = 1;
          }
        add(deltas[d] == 0 ? "singular" : "near_singular", p, deltas[d]);
        if (deltas[d] == 0 && k > 0) states.pop_back();  // one state exactly at the singularity
      }
  }
  return states;
}

}  // namespace sweepgen::report
