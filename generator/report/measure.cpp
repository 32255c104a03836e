#include "report/measure.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "solver/reference_solver.hpp"

namespace sweepgen::report {
namespace {

class Random {
 public:
  explicit Random(unsigned long long seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  spatial::Force<double> wrench(double moment, double force) {
    spatial::Force<double> f;
    for (int k = 0; k < 3; ++k) {
      f.moment[k] = uniform(-moment, moment);
      f.force[k] = uniform(-force, force);
    }
    return f;
  }

 private:
  std::mt19937_64 rng_;
};

template <class Vector>
void append(std::vector<double>& flat, const Vector& v) {
  flat.insert(flat.end(), v.data(), v.data() + v.size());
}

double condition_number(const solver::ConstraintMatrix<Precise>& E) {
  if (E.rows() == 0) return 1;
  const Eigen::MatrixXd Ed = E.cast<double>();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(Ed).singularValues();
  return sv(sv.size() - 1) > 0 ? sv(0) / sv(sv.size() - 1) : std::numeric_limits<double>::infinity();
}

template <class Vector>
std::vector<Precise> widen(const Vector& v) {
  std::vector<Precise> w(static_cast<std::size_t>(v.size()));
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<Precise>(v[static_cast<Eigen::Index>(i)]);
  return w;
}

}  // namespace

std::size_t flat_in_size(const scene::Scene& s, const model::Chain& chain) {
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  return 2 * n + s.layout.torques.size() * n + 6 * s.layout.external_forces.size() +
         (s.fixed_directions.empty() ? 6 * nc : 0) + nc;
}

std::vector<Problem> random_problems(const scene::Scene& s, const model::Chain& chain, std::size_t count,
                                     unsigned long long seed) {
  Random random(seed);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  std::vector<Problem> problems(count);
  for (Problem& p : problems) {
    p.q.resize(static_cast<Eigen::Index>(n));
    p.qd.resize(static_cast<Eigen::Index>(n));
    for (std::size_t i = 1; i <= n; ++i) {
      const auto& j = chain.joints[i];
      p.q[static_cast<Eigen::Index>(i - 1)] =
          random.uniform(std::isfinite(j.lower) ? j.lower : -M_PI, std::isfinite(j.upper) ? j.upper : M_PI);
    }
    for (auto& v : p.qd) v = random.uniform(-2, 2);
    p.tau_ff = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    for (std::size_t t = 0; t < s.layout.torques.size(); ++t) {
      const double fraction = t == 0 ? 1.5 : 0.2;
      Eigen::VectorXd tau(static_cast<Eigen::Index>(n));
      for (std::size_t i = 1; i <= n; ++i) {
        const double limit = std::isfinite(chain.joints[i].effort_limit) && chain.joints[i].effort_limit > 0
                                 ? chain.joints[i].effort_limit
                                 : 10.0;
        tau[static_cast<Eigen::Index>(i - 1)] = random.uniform(-fraction * limit, fraction * limit);
      }
      p.tau_ff += tau;
      p.torques.push_back(tau);
    }
    for (std::size_t e = 0; e < s.layout.external_forces.size(); ++e) p.wrenches.push_back(random.wrench(2, 20));
    p.alpha = s.fixed_directions;
    if (p.alpha.empty())
      for (std::size_t k = 0; k < nc; ++k) {
        const spatial::Force<double> f = random.wrench(1, 1);
        p.alpha.push_back(f * (1.0 / std::sqrt(f.moment.squaredNorm() + f.force.squaredNorm())));
      }
    p.beta.resize(static_cast<Eigen::Index>(nc));
    for (auto& b : p.beta) b = random.uniform(-3, 3);

    append(p.flat, p.q);
    append(p.flat, p.qd);
    for (const auto& t : p.torques) append(p.flat, t);
    for (const auto& w : p.wrenches) {
      append(p.flat, w.moment);
      append(p.flat, w.force);
    }
    if (s.fixed_directions.empty())
      for (const auto& a : p.alpha) {
        append(p.flat, a.moment);
        append(p.flat, a.force);
      }
    append(p.flat, p.beta);
  }
  return problems;
}

std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems) {
  solver::ReferenceSolver<Precise> reference(chain, s.layout, s.solver_options());
  const auto cast = [](const spatial::Force<double>& f) {
    return spatial::Force<Precise>{f.moment.cast<Precise>(), f.force.cast<Precise>()};
  };
  std::vector<Truth> truth;
  truth.reserve(problems.size());
  for (const Problem& p : problems) {
    reference.outward(p.q.cast<Precise>(), p.qd.cast<Precise>());
    auto& d = reference.drivers();
    for (std::size_t t = 0; t < p.torques.size(); ++t) d.torques[t] = p.torques[t].cast<Precise>();
    for (std::size_t e = 0; e < p.wrenches.size(); ++e) d.external_forces[e] = cast(p.wrenches[e]);
    for (std::size_t k = 0; k < p.alpha.size(); ++k) d.constraint_directions[k] = cast(p.alpha[k]);
    reference.decompose();
    const auto& r = reference.solve(solver::Policy::original, p.beta.cast<Precise>());
    truth.push_back({widen(r.qdd), widen(r.tau_cmd), condition_number(reference.articulated().body[0].constraint_energy)});
  }
  return truth;
}

VariantResult measure_reference_double(const scene::Scene& s, const model::Chain& chain,
                                       const std::vector<Problem>& problems, const TimingOptions& timing) {
  solver::ReferenceSolver<double> reference(chain, s.layout, s.solver_options());
  const std::size_t n = chain.dof(), stride = 2 * n + 7;
  // Results go to a plain buffer inside the timed loop (as the generated code's do), widened after.
  std::vector<double> out(problems.size() * stride);
  unsigned rank_deficient_bit = solver::status_constraint_rank_deficient;
  const auto run_all = [&] {
    double* o = out.data();
    for (const Problem& p : problems) {
      reference.outward(p.q, p.qd);
      auto& d = reference.drivers();
      for (std::size_t t = 0; t < p.torques.size(); ++t) d.torques[t] = p.torques[t];
      for (std::size_t e = 0; e < p.wrenches.size(); ++e) d.external_forces[e] = p.wrenches[e];
      for (std::size_t k = 0; k < p.alpha.size(); ++k) d.constraint_directions[k] = p.alpha[k];
      reference.decompose();
      const auto& r = reference.solve(solver::Policy::original, p.beta);
      for (std::size_t i = 0; i < n; ++i) {
        o[i] = r.qdd[static_cast<Eigen::Index>(i)];
        o[n + i] = r.tau_cmd[static_cast<Eigen::Index>(i)];
      }
      for (int k = 0; k < 3; ++k) {
        o[2 * n + k] = r.tip_acceleration.angular[k];
        o[2 * n + 3 + k] = r.tip_acceleration.linear[k];
      }
      o[2 * n + 6] = static_cast<double>(reference.status());
      o += stride;
    }
  };
  VariantResult result{"reference", "double", "", time_passes(problems.size(), timing, run_all), {}};
  for (std::size_t state = 0; state < problems.size(); ++state) {
    const double* o = out.data() + state * stride;
    Outcome outcome;
    outcome.qdd.assign(o, o + n);
    outcome.tau_cmd.assign(o + n, o + 2 * n);
    for (int k = 0; k < 6; ++k) outcome.tip_acceleration[static_cast<std::size_t>(k)] = o[2 * n + k];
    outcome.rank_deficient = static_cast<unsigned>(o[2 * n + 6]) & rank_deficient_bit;
    result.outcomes.push_back(std::move(outcome));
  }
  return result;
}

template <class Scalar>
VariantResult measure_generated(FlatSolve<Scalar> solve, const char* scalar_name, std::size_t dof,
                                std::size_t constraints, const std::vector<Problem>& problems,
                                const TimingOptions& timing) {
  const std::size_t n = dof, nc = constraints;
  const std::size_t in_size = problems.empty() ? 0 : problems.front().flat.size(), out_size = 3 * n + nc + 7;
  std::vector<Scalar> in(problems.size() * in_size), out(problems.size() * out_size);
  for (std::size_t state = 0; state < problems.size(); ++state)
    for (std::size_t i = 0; i < in_size; ++i) in[state * in_size + i] = static_cast<Scalar>(problems[state].flat[i]);
  const auto run_all = [&] {
    const Scalar* i = in.data();
    Scalar* o = out.data();
    for (std::size_t state = 0; state < problems.size(); ++state, i += in_size, o += out_size) solve(i, o);
  };
  VariantResult result{"generated", scalar_name, "", time_passes(problems.size(), timing, run_all), {}};
  for (std::size_t state = 0; state < problems.size(); ++state) {
    const Scalar* o = out.data() + state * out_size;
    Outcome outcome;
    outcome.qdd.assign(o, o + n);
    outcome.tau_cmd.assign(o + n, o + 2 * n);
    for (std::size_t k = 0; k < 6; ++k) outcome.tip_acceleration[k] = o[3 * n + nc + k];
    outcome.rank_deficient = static_cast<unsigned>(o[3 * n + nc + 6]) & solver::status_constraint_rank_deficient;
    result.outcomes.push_back(std::move(outcome));
  }
  return result;
}

template VariantResult measure_generated<double>(FlatSolve<double>, const char*, std::size_t, std::size_t,
                                                 const std::vector<Problem>&, const TimingOptions&);
template VariantResult measure_generated<float>(FlatSolve<float>, const char*, std::size_t, std::size_t,
                                                const std::vector<Problem>&, const TimingOptions&);

Precise relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b) {
  Precise diff = 0, scale = 1;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  // NaN in the answer is the worst error there is.
  for (const Precise v : a)
    if (!std::isfinite(v)) return std::numeric_limits<Precise>::infinity();
  return diff / scale;
}

Summary summarize(const VariantResult& result, const std::vector<Problem>& problems, const std::vector<Truth>& truth) {
  Summary summary;
  summary.states = problems.size();
  summary.ns_median = quantile(result.ns_per_solve, 0.5);
  summary.ns_p90 = quantile(result.ns_per_solve, 0.9);
  std::vector<Precise> qdd_errors;
  for (std::size_t state = 0; state < result.outcomes.size(); ++state) {
    const Outcome& o = result.outcomes[state];
    const Problem& p = problems[state];
    const Truth& t = truth[state];
    const Precise e_qdd = relative_error(o.qdd, t.qdd);
    if (!(t.cond <= kIllConditioned)) {
      ++summary.ill_conditioned_states;
      summary.ill_conditioned_max_rel_err_qdd = std::max(summary.ill_conditioned_max_rel_err_qdd, e_qdd);
      continue;
    }
    if (o.rank_deficient)
      ++summary.rank_deficient_well_conditioned;
    else
      summary.max_rel_err_qdd_full_rank = std::max(summary.max_rel_err_qdd_full_rank, e_qdd);
    qdd_errors.push_back(e_qdd);
    summary.max_rel_err_qdd = std::max(summary.max_rel_err_qdd, e_qdd);
    summary.max_rel_err_tau = std::max(summary.max_rel_err_tau, relative_error(o.tau_cmd, t.tau_cmd));
    // |alpha_k^T Xdd_tip - beta_k| / max(1, |beta|_inf, |Xdd_tip|_inf), worst k.
    Precise scale = 1, worst = 0;
    for (const Precise v : o.tip_acceleration) scale = std::max(scale, std::abs(v));
    for (Eigen::Index k = 0; k < p.beta.size(); ++k) scale = std::max(scale, static_cast<Precise>(std::abs(p.beta[k])));
    for (std::size_t k = 0; k < p.alpha.size(); ++k) {
      Precise projection = 0;
      for (int c = 0; c < 3; ++c)
        projection += static_cast<Precise>(p.alpha[k].moment[c]) * o.tip_acceleration[static_cast<std::size_t>(c)] +
                      static_cast<Precise>(p.alpha[k].force[c]) * o.tip_acceleration[static_cast<std::size_t>(3 + c)];
      worst = std::max(worst, std::abs(projection - static_cast<Precise>(p.beta[static_cast<Eigen::Index>(k)])));
    }
    for (const Precise v : o.tip_acceleration)
      if (!std::isfinite(v)) worst = std::numeric_limits<Precise>::infinity();
    summary.max_constraint_residual = std::max(summary.max_constraint_residual, worst / scale);
  }
  summary.median_rel_err_qdd = quantile(qdd_errors, 0.5);
  if (qdd_errors.empty()) {
    const Precise nan = std::numeric_limits<Precise>::quiet_NaN();
    summary.max_rel_err_qdd = summary.max_rel_err_tau = summary.max_constraint_residual = nan;
  }
  if (summary.ill_conditioned_states == 0) summary.ill_conditioned_max_rel_err_qdd = 0;
  return summary;
}

}  // namespace sweepgen::report
