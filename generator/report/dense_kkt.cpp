#include "report/dense_kkt.hpp"

#include "report/dense_dynamics.hpp"

namespace sweepgen::report {

VariantResult measure_dense_kkt(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                                const TimingOptions& timing) {
  using Dynamics = DenseDynamics<double>;
  // A floating base's gravity is turned by each state's base rotation (O4): one oracle per state.
  std::vector<Dynamics> per_state;
  for (const Problem& p : problems)
    per_state.emplace_back(chain, chain.floating_base ? model::Vec3(p.base_rotation.transpose() * s.gravity) : s.gravity);
  const std::string& tip = chain.tip_link;
  const std::size_t nc = s.layout.constraints;
  const std::vector<std::string> links = solver::direction_links(s.layout, chain);  // per direction, its set's link
  struct Posed {
    std::vector<Dynamics::ExternalWrench> wrenches;
    Dynamics::Mat alpha;
  };
  std::vector<Posed> posed;
  for (const Problem& p : problems) {
    Posed x{{}, Dynamics::Mat(6, static_cast<Eigen::Index>(nc))};
    for (std::size_t e = 0; e < p.wrenches.size(); ++e) {
      Dynamics::Six w;
      w << p.wrenches[e].moment, p.wrenches[e].force;
      x.wrenches.push_back({s.layout.external_forces[e].link, w});
    }
    for (std::size_t k = 0; k < nc; ++k) x.alpha.col(static_cast<Eigen::Index>(k)) << p.alpha[k].moment, p.alpha[k].force;
    posed.push_back(std::move(x));
  }
  std::vector<Dynamics::KktSolution> solutions(problems.size());
  const auto call = [&](std::size_t state) {
    const Problem& p = problems[state];
    solutions[state] = per_state[state].solve_kkt(p.q, p.qd, p.tau_ff, posed[state].wrenches, links, posed[state].alpha, p.beta);
  };
  VariantResult result{"dense_kkt", "double", "", time_calls(problems.size(), timing, call), {}};
  for (std::size_t state = 0; state < problems.size(); ++state) {
    const Problem& p = problems[state];
    const Dynamics::KktSolution& x = solutions[state];
    const Dynamics& dynamics = per_state[state];
    const Eigen::VectorXd qdd = dynamics.in_solver_coordinates(p.q, p.qd, x.qdd);
    Outcome o;
    // τcmd = τff + Jcᵀ ν (T1), Ẍ_link = J_link q̈ + c: outside the timed call.
    const Eigen::VectorXd tau_cmd =
        p.tau_ff + dynamics.constraint_jacobian(p.q, links, posed[state].alpha).transpose() * x.nu;
    const Dynamics::Six tip_acceleration = dynamics.spatial_acceleration(p.q, p.qd, x.qdd, tip);
    for (const std::string& link : links) {
      const Dynamics::Six a = dynamics.spatial_acceleration(p.q, p.qd, x.qdd, link);
      o.link_acceleration.push_back({});
      for (std::size_t c = 0; c < 6; ++c) o.link_acceleration.back()[c] = a[static_cast<Eigen::Index>(c)];
    }
    o.qdd.assign(qdd.data(), qdd.data() + qdd.size());
    o.nu.assign(x.nu.data(), x.nu.data() + x.nu.size());
    o.tau_cmd.assign(tau_cmd.data(), tau_cmd.data() + tau_cmd.size());
    for (std::size_t k = 0; k < 6; ++k) o.tip_acceleration[k] = tip_acceleration[static_cast<Eigen::Index>(k)];
    result.outcomes.push_back(std::move(o));
  }
  return result;
}

}  // namespace sweepgen::report
