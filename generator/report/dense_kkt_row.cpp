#include "report/dense_kkt_row.hpp"

#include "oracle/dense_kkt.hpp"

namespace sweepgen::report {

VariantResult measure_dense_kkt(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                                const TimingOptions& timing) {
  using Dynamics = oracle::DenseDynamics<double>;
  // The rows of sets on one link each: the relative rows of a loop (L2) and a coupling's (M1) are
  // the tests' (tests/test_loop_sets.cpp, tests/test_coupled_mimics.cpp), not this row's.
  if (s.layout.loop_sets() > 0)
    return {"dense_kkt", "double",
            "the dense KKT row takes sets on one link; a set between two links is held to its relative rows by "
            "tests/test_loop_sets.cpp",
            {}, {}};
  if (!chain.couplings.empty())
    return {"dense_kkt", "double",
            "the dense KKT row takes no coupled <mimic> joints; tests/test_coupled_mimics.cpp holds the solver to their "
            "rows",
            {}, {}};
  std::vector<oracle::DenseKktProblem> posed;
  for (const Problem& p : problems) posed.emplace_back(s, chain, p);
  const std::string& tip = chain.tip_link;
  std::vector<Dynamics::KktSolution> solutions(problems.size());
  const auto call = [&](std::size_t state) { solutions[state] = posed[state].solve(problems[state]); };
  VariantResult result{"dense_kkt", "double", "", time_calls(problems.size(), timing, call), {}};
  for (std::size_t state = 0; state < problems.size(); ++state) {
    const Problem& p = problems[state];
    const Dynamics::KktSolution& x = solutions[state];
    const Dynamics& dynamics = posed[state].dynamics;
    const std::vector<std::string>& links = posed[state].links;
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
