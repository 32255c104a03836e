#include "report/measure.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "oracle/condition_number.hpp"
#include "oracle/relative_error.hpp"
#include "solver/joint_inertia.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::report {
namespace {

// Truth::tau_constraint_terms: each direction's share of J_cᵀ ν (T1), propagated rigidly from
// the body its set acts on, like solver/commanded_torque.hpp's sum, in absolute value.
std::vector<Precise> constraint_torque_terms(const solver::ReferenceSolver<Precise>& reference,
                                             const solver::ConstraintVector<Precise>& nu) {
  const std::size_t n = reference.dof();
  std::vector<Precise> terms(n, Precise(0));
  const solver::SolverModel<Precise>& model = reference.model();
  for (Eigen::Index k = 0; k < nu.size(); ++k) {
    if (static_cast<std::size_t>(k) >= model.set_directions()) {  // a coupling's torque pair τ_c ν_k (M2)
      for (std::size_t i = 1; i <= n; ++i) terms[i - 1] += abs(solver::coupling_torque_at(model, static_cast<std::size_t>(k), i) * nu[k]);
      continue;
    }
    const std::size_t body = model.set_of(static_cast<std::size_t>(k)).body;
    spatial::Force<Precise> f = reference.articulated().body[body].constraint_force[static_cast<std::size_t>(k)] * nu[k];
    for (std::size_t i = body; i >= 1; --i) {
      terms[i - 1] += abs(spatial::dot(f, reference.model().joints[i].S));
      f = reference.kinematics().body[i].X.apply_transpose(f);
    }
  }
  return terms;
}

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

template <class Vector>
std::vector<Precise> widen(const Vector& v) {
  std::vector<Precise> w(static_cast<std::size_t>(v.size()));
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<Precise>(v[static_cast<Eigen::Index>(i)]);
  return w;
}

}  // namespace

double clock_overhead_ns() {
  std::vector<double> empty(1001);
  for (double& ns : empty) {
    const auto start = std::chrono::steady_clock::now();
    const auto stop = std::chrono::steady_clock::now();
    ns = std::chrono::duration<double, std::nano>(stop - start).count();
  }
  return quantile(empty, 0.5);
}

double inertia_condition_number(const model::Chain& chain, const solver::JointVector<Precise>& q,
                                solver::SolverOptions options) {
  options.gravity.setZero();
  solver::DriverLayout layout;
  layout.torques = {"tau"};
  layout.compose_all();
  solver::ReferenceSolver<Precise> solver(chain, layout, options);
  const Eigen::Index n = q.size();
  solver.outward(q, solver::JointVector<Precise>::Zero(n));
  const solver::ConstraintVector<Precise> no_setpoints;
  const auto qdd = [&](const solver::JointVector<Precise>& tau) {
    solver.drivers().torques[0] = tau;
    solver.decompose();
    const solver::JointVector<Precise> a = solver.solve(solver::Policy::original, no_setpoints).qdd;
    return std::make_pair(a, solver.status());
  };
  const auto [qdd_unforced, status] = qdd(solver::JointVector<Precise>::Zero(n));
  if (status & solver::status_joint_inertia_singular) return std::numeric_limits<double>::infinity();
  Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> M_inv(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    M_inv.col(j) = (qdd(solver::JointVector<Precise>::Unit(n, j)).first - qdd_unforced).cast<long double>();
  return oracle::condition_number(M_inv);
}

void pack_flat(const scene::Scene& s, const model::Chain& chain, Problem& p) {
  p.flat = solver::flat_input(p, s.flat_layout(chain));
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
    p.alpha = solver::directions_with(s.layout, [&random] {
      const spatial::Force<double> f = random.wrench(1, 1);
      return f * (1.0 / std::sqrt(f.moment.squaredNorm() + f.force.squaredNorm()));
    });
    p.beta.resize(static_cast<Eigen::Index>(nc));
    for (auto& b : p.beta) b = random.uniform(-3, 3);
    if (chain.floating_base)
      p.base_rotation = Eigen::Quaterniond(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1),
                                           random.uniform(-1, 1)).normalized().toRotationMatrix();

    pack_flat(s, chain, p);
  }
  return problems;
}

std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems) {
  return precise_reference(s, chain, problems, s.solver_options());
}

std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems, const solver::SolverOptions& options,
                                     solver::Policy policy, bool with_cond_M) {
  solver::ReferenceSolver<Precise> reference(chain, s.layout, options);
  std::vector<Truth> truth;
  truth.reserve(problems.size());
  for (const Problem& p : problems) {
    const auto& r = reference.run(p.cast<Precise>(), policy);
    auto& d = reference.drivers();
    const auto& E = reference.articulated().body[0].constraint_energy;
    Truth t{widen(r.qdd),
            widen(r.tau_cmd),
            widen(r.nu.head(static_cast<Eigen::Index>(s.layout.constraints))),  // the sets' (the couplings' after them, M2)
            {},
            {},
            oracle::condition_number(E),
            oracle::scaled_condition_number(E),
            static_cast<double>(solver::min_relative_joint_inertia(reference.model(), reference.articulated())),
            with_cond_M ? inertia_condition_number(chain, p.q.cast<Precise>(), options) : NAN,
            reference.status()};
    t.tau_constraint_terms = constraint_torque_terms(reference, r.nu);
    // The same state with α = 0: every pivot is 0, so ν = 0 and q̈ is the free motion.
    for (std::size_t k = 0; k < p.alpha.size(); ++k) d.constraint_directions[k] = spatial::Force<Precise>{};
    if (!p.alpha.empty()) {
      reference.decompose();
      t.qdd_free = widen(reference.solve(policy, p.beta.cast<Precise>()).qdd);
    } else {
      t.qdd_free = t.qdd;
    }
    truth.push_back(std::move(t));
  }
  return truth;
}

solver::SolverOptions with_tolerance_factor(const scene::Scene& s, double factor, double eps) {
  solver::SolverOptions o = s.solver_options();
  o.pivot_tolerance = factor * o.pivot_tolerance_for(eps);
  o.joint_inertia_tolerance = factor * o.joint_inertia_tolerance_for(eps);
  return o;
}

template <class Scalar>
Outcome outcome_of(const Scalar* o, const solver::FlatLayout& layout) {
  const solver::SolveOutputs& listed = layout.outputs;
  Outcome outcome;
  if (listed.qdd) outcome.qdd.assign(o + layout.qdd(), o + layout.qdd() + layout.dof);
  if (listed.tau_cmd) outcome.tau_cmd.assign(o + layout.tau_cmd(), o + layout.tau_cmd() + layout.dof);
  if (listed.nu) outcome.nu.assign(o + layout.nu(), o + layout.nu() + layout.constraints);
  if (listed.tip_acceleration)
    for (std::size_t k = 0; k < 6; ++k) outcome.tip_acceleration[k] = o[layout.tip_acceleration() + k];
  if (layout.has_link_acceleration())
    for (std::size_t k = 0; k < layout.constraints; ++k) {
      std::array<Precise, 6> a{};
      for (std::size_t c = 0; c < 6; ++c) a[c] = o[layout.link_acceleration(k) + c];
      outcome.link_acceleration.push_back(a);
    }
  outcome.status = static_cast<unsigned>(o[layout.status()]);
  outcome.rank_deficient = outcome.status & solver::status_constraint_rank_deficient;
  return outcome;
}
template Outcome outcome_of<double>(const double*, const solver::FlatLayout&);
template Outcome outcome_of<float>(const float*, const solver::FlatLayout&);

namespace {

// ReferenceSolver<Scalar> on the states (inputs rounded to Scalar outside the timed calls).
template <class Scalar>
VariantResult measure_reference(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                                const TimingOptions& timing, const char* scalar_name) {
  solver::ReferenceSolver<Scalar> reference(chain, s.layout, s.solver_options());
  const solver::FlatLayout layout = s.flat_layout(chain);
  // Results go to a plain buffer in the timed calls (as the generated code's do), widened after.
  std::vector<Scalar> out(problems.size() * layout.out_size());
  std::vector<solver::SolveInputs<Scalar>> inputs;
  for (const Problem& p : problems) inputs.push_back(p.template cast<Scalar>());
  const auto call = [&](std::size_t state) {
    const auto& solution = reference.run(inputs[state], solver::Policy::original);
    solver::flat_output(solution, reference.status(), layout, out.data() + state * layout.out_size());
  };
  VariantResult result{"reference", scalar_name, "", time_calls(problems.size(), timing, call), {}};
  for (std::size_t state = 0; state < problems.size(); ++state)
    result.outcomes.push_back(outcome_of(out.data() + state * layout.out_size(), layout));
  return result;
}
}  // namespace

VariantResult measure_reference_double(const scene::Scene& s, const model::Chain& chain,
                                       const std::vector<Problem>& problems, const TimingOptions& timing) {
  return measure_reference<double>(s, chain, problems, timing, "double");
}

VariantResult measure_reference_precise(const scene::Scene& s, const model::Chain& chain,
                                        const std::vector<Problem>& problems, const TimingOptions& timing) {
  return measure_reference<Precise>(s, chain, problems, timing, "binary128");
}

VariantResult measure_reference_float(const scene::Scene& s, const model::Chain& chain,
                                      const std::vector<Problem>& problems, const TimingOptions& timing) {
  return measure_reference<float>(s, chain, problems, timing, "float");
}

template <class Scalar>
VariantResult measure_generated(FlatSolve<Scalar> solve, const char* scalar_name, const solver::FlatLayout& layout,
                                const std::vector<Problem>& problems, const TimingOptions& timing) {
  const std::size_t in_size = problems.empty() ? 0 : problems.front().flat.size(), out_size = layout.out_size();
  std::vector<Scalar> in(problems.size() * in_size), out(problems.size() * out_size);
  for (std::size_t state = 0; state < problems.size(); ++state)
    for (std::size_t i = 0; i < in_size; ++i) in[state * in_size + i] = static_cast<Scalar>(problems[state].flat[i]);
  const auto call = [&](std::size_t state) { solve(in.data() + state * in_size, out.data() + state * out_size); };
  VariantResult result{"generated", scalar_name, "", time_calls(problems.size(), timing, call), {}};
  for (std::size_t state = 0; state < problems.size(); ++state)
    result.outcomes.push_back(outcome_of(out.data() + state * out_size, layout));
  return result;
}

template VariantResult measure_generated<double>(FlatSolve<double>, const char*, const solver::FlatLayout&,
                                                 const std::vector<Problem>&, const TimingOptions&);
template VariantResult measure_generated<float>(FlatSolve<float>, const char*, const solver::FlatLayout&,
                                                const std::vector<Problem>&, const TimingOptions&);

Precise constraint_residual(const Outcome& o, const Problem& p) {
  if (o.link_acceleration.size() != p.alpha.size()) return std::numeric_limits<Precise>::quiet_NaN();
  Precise scale = 1, worst = 0;
  for (const auto& a : o.link_acceleration)
    for (const Precise v : a) {
      if (!isfinite(v)) return std::numeric_limits<Precise>::infinity();
      scale = std::max(scale, abs(v));
    }
  for (Eigen::Index k = 0; k < p.beta.size(); ++k) scale = std::max(scale, static_cast<Precise>(std::abs(p.beta[k])));
  for (std::size_t k = 0; k < p.alpha.size(); ++k) {
    const std::array<Precise, 6>& a = o.link_acceleration.at(k);
    Precise projection = 0;
    for (std::size_t c = 0; c < 3; ++c)
      projection += static_cast<Precise>(p.alpha[k].moment[static_cast<int>(c)]) * a[c] +
                    static_cast<Precise>(p.alpha[k].force[static_cast<int>(c)]) * a[3 + c];
    worst = std::max(worst, abs(projection - static_cast<Precise>(p.beta[static_cast<Eigen::Index>(k)])));
  }
  return worst / scale;
}

}  // namespace sweepgen::report
