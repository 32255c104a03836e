// The reference ACHD solver (double) against an independent dense oracle in long double
// (generator/oracle/dense_dynamics.hpp): Newton–Euler inverse dynamics, M(q) from its columns,
// the tip's body Jacobian and drift, and Gauss' principle as one KKT system
//   [M −Jc^T; Jc 0] [q̈; ν] = [τff + Σ J_i^T F_ext,i − b; β − α^T c],   Jc = α^T J_tip.
// The oracle itself is first checked against finite differences and the Lagrangian.
//
// Cases: the four bundled robots at their default tips (behind fixed joints; every other joint
// with rotor inertia) with 1000 random states per Nc ∈ {0, 1, 3, 6}, and 1000 random chains
// (1..10 joints, revolute and prismatic, rotor inertia, lumped tip frames) with a random state
// per Nc. Where Nc exceeds what the tip can do (Nc > N, the planar robot's Nc = 6) the solver
// drops pivots; the oracle then solves for the constraints the documented pivot policy keeps.
#include <gtest/gtest.h>

#include <tuple>

#include <iostream>

#include "support/oracle_problem.hpp"
#include "support/state_count.hpp"
#include "support/skip_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using test::LongDouble;
using test::Oracle;
using test::OracleMat;
using test::OracleVec;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Finite differences in long double with step 1e-5: truncation ~h^2 = 1e-10, rounding
// ~eps_ld/h = 1e-14, relative to max(1, |value|).
constexpr double kFiniteDifferenceTolerance = 1e-8;
// Identities the oracle satisfies by algebra, evaluated in long double (eps 1.1e-19) on
// quantities of size <= 1e4: 1e-14 leaves 1e5 ulps of headroom for cancellation.
constexpr double kOracleAlgebraTolerance = 1e-14;
// Solver (double) vs oracle, ‖a−b‖∞ / max(1, ‖b‖∞), floor of the tolerance for q̈ and ν.
constexpr double kAgreementTolerance = 1e-10;
// Constraint residual ‖α^T Ẍ_tip − β‖∞ / max(1, ‖β‖∞, ‖Ẍ_tip‖∞) (α columns are unit vectors, so
// rounding is relative to the size of Ẍ_tip's components), floor of its tolerance.
constexpr double kResidualTolerance = 1e-11;
// E^A_cstr,0 vs α^T J M^-1 J^T α, relative to ‖E‖max: the inward sweep is a sequence of O(N)
// rank-one updates of PSD matrices, no cancellation to amplify rounding; 1e-11 is ~5e4 ulps.
constexpr double kEnergyTolerance = 1e-11;
// Statistics split: cond(E) above this counts as ill-conditioned.
constexpr double kWellConditioned = 1e6;
// The tolerances grow as 10·eps·cond(E)·kConditionFactor once that exceeds their floor. A
// double solve loses ~eps·cond(E) relative to ν (E itself is accurate to ~1e-15, see the E
// identity); q̈ and Ẍ_tip receive that error through M^-1 J^T α ν, whose size relative to q̈ adds
// up to another order of magnitude (measured max error/(eps·cond): q̈ 9.9, ν 1.0, residual 9.6
// over the 20000 states below); the factor 10 puts the tolerance 10x above the worst of those.
// Hence the fixed 1e-10 bound holds up to cond(E) ~ 4.5e4; beyond, the bound is 100·eps·cond.
constexpr double kConditionFactor = 10;

// The largest tolerance ever applied: a state whose scaled tolerance would exceed it
// (cond(E) > 1e9) has its q̈, ν and residual left unjudged, counted and bounded in share (below);
// there a double solve may legitimately be off by more than 1e-5, and a tolerance that kept
// growing would accept anything.
constexpr double kCeiling = 1e-5;
double scaled_tolerance(double floor, LongDouble cond) {
  return std::max(floor, 10 * kEps * static_cast<double>(cond) * kConditionFactor);
}
bool judged(LongDouble cond) { return scaled_tolerance(0, cond) <= kCeiling; }

// ---------------------------------------------------------------------------------------------
// The oracle against finite differences and the Lagrangian.

struct Fd {
  static constexpr LongDouble h = 1e-5L;
};

Oracle::V3 vee(const Oracle::M3& W) { return Oracle::V3(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1)) / 2; }

// Twist [ω; v] of `link` in its own coordinates along q(t) = q + t q̇, from poses only.
Oracle::Six finite_difference_twist(const Oracle& o, const OracleVec& q, const OracleVec& qd, const std::string& link) {
  const Oracle::Pose plus = o.link_pose(q + Fd::h * qd, link), minus = o.link_pose(q - Fd::h * qd, link),
                     here = o.link_pose(q, link);
  const Oracle::M3 Rdot = (plus.R - minus.R) / (2 * Fd::h);
  const Oracle::V3 omega = vee(Rdot * here.R.transpose());
  const Oracle::V3 v = (plus.p - minus.p) / (2 * Fd::h);
  Oracle::Six t;
  t << here.R.transpose() * omega, here.R.transpose() * v;
  return t;
}

double relative(const OracleVec& a, const OracleVec& b) {
  const LongDouble scale = std::max<LongDouble>(1, b.cwiseAbs().maxCoeff());
  return static_cast<double>((a - b).cwiseAbs().maxCoeff() / scale);
}

// Kinetic-energy form of M: Σ_i over body frames of m Jv^T Jv + Jω^T I_o Jω + cross terms
// (v·(ω×h) with h the first moment), plus the rotor inertias, all from body Jacobians.
OracleMat mass_matrix_from_jacobians(const Oracle& o, const model::Chain& chain, const OracleVec& q) {
  const std::size_t n = chain.dof();
  OracleMat M = OracleMat::Zero(n, n);
  for (std::size_t i = 1; i <= n; ++i) {
    const Oracle::Jacobian J = o.jacobian(q, chain.bodies[i].link);
    const model::Inertia& I = chain.bodies[i].inertia;
    const LongDouble m = I.C(0, 0);
    const Oracle::V3 h(I.B(2, 1), I.B(0, 2), I.B(1, 0));
    const OracleMat Jw = J.topRows(3), Jv = J.bottomRows(3);
    const Oracle::M3 hx = spatial::skew<LongDouble>(h);
    // KE = ½ (ω^T I_o ω + m v^T v + 2 v^T (ω × h)),  v^T (ω × h) = v^T hx^T ω.
    const OracleMat cross = Jv.transpose() * hx.transpose() * Jw;
    M += Jw.transpose() * I.A.cast<LongDouble>() * Jw + m * Jv.transpose() * Jv + cross + cross.transpose();
    M(i - 1, i - 1) += chain.joints[i].rotor_inertia;
  }
  return M;
}

void check_oracle(const test::OracleCase& c, test::RandomProblem& random, double& worst_fd, double& worst_algebra,
                  test::SkipCount& skips) {
  const Oracle o(c.chain);
  const std::size_t n = c.chain.dof();
  const test::OracleProblem p = test::draw_problem(random, c, 0);
  const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd), tau = test::to_long(p.tau_ff);
  OracleVec qdd(n);
  for (auto& x : qdd) x = random.uniform(-5, 5);
  const auto ext = p.oracle_wrenches(c);

  // Jacobian and twist vs the time derivative of the pose, for the tip and the force links.
  std::vector<std::string> links = c.external_links;
  links.push_back(c.chain.tip_link);
  for (const auto& link : links) {
    const Oracle::Six fd = finite_difference_twist(o, q, qd, link);
    worst_fd = std::max(worst_fd, relative(o.jacobian(q, link) * qd, fd));
    worst_algebra = std::max(worst_algebra, relative(o.twist(q, qd, link), o.jacobian(q, link) * qd));
  }

  // Spatial acceleration minus gravity vs the time derivative of the twist along
  // q(t) = q + t q̇ + ½ t² q̈, plus the gravity term [0; −R^T g]; and Ẍ = J q̈ + c.
  {
    const std::string& tip = c.chain.tip_link;
    const auto twist_at = [&](LongDouble t) { return o.twist(q + t * qd + t * t / 2 * qdd, qd + t * qdd, tip); };
    Oracle::Six fd = (twist_at(Fd::h) - twist_at(-Fd::h)) / (2 * Fd::h);
    fd.tail<3>() -= o.link_pose(q, tip).R.transpose() * Oracle::V3(0, 0, -9.81L);
    const Oracle::Six acc = o.spatial_acceleration(q, qd, qdd, tip);
    worst_fd = std::max(worst_fd, relative(acc, fd));
    worst_algebra = std::max(worst_algebra, relative(o.jacobian(q, tip) * qdd + o.drift(q, qd, tip), acc));
  }

  // M from inverse dynamics vs M from kinetic energy (Jacobians), symmetric.
  const OracleMat M = o.mass_matrix(q);
  worst_algebra = std::max(worst_algebra, relative(M.reshaped(), mass_matrix_from_jacobians(o, c.chain, q).reshaped()));
  worst_algebra = std::max(worst_algebra, relative(M.reshaped(), OracleMat(M.transpose()).reshaped()));

  // Gravity torques = ∂V/∂q.
  const OracleVec zero = OracleVec::Zero(n);
  const OracleVec gravity = o.bias(q, zero);
  OracleVec dV(n);
  for (std::size_t k = 0; k < n; ++k) {
    const OracleVec e = OracleVec::Unit(n, k) * Fd::h;
    dV[k] = (o.potential_energy(q + e) - o.potential_energy(q - e)) / (2 * Fd::h);
  }
  worst_fd = std::max(worst_fd, relative(gravity, dV));

  // Velocity terms from the Lagrangian: b(q, q̇) − g(q) = Ṁ q̇ − ½ ∂(q̇^T M q̇)/∂q.
  const OracleMat Mdot = (o.mass_matrix(q + Fd::h * qd) - o.mass_matrix(q - Fd::h * qd)) / (2 * Fd::h);
  OracleVec dT(n);
  for (std::size_t k = 0; k < n; ++k) {
    const OracleVec e = OracleVec::Unit(n, k) * Fd::h;
    dT[k] = (qd.dot(o.mass_matrix(q + e) * qd) - qd.dot(o.mass_matrix(q - e) * qd)) / (4 * Fd::h);
  }
  worst_fd = std::max(worst_fd, relative(o.bias(q, qd) - gravity, Mdot * qd - dT));

  // Inverse dynamics is M q̈ + b, and external wrenches enter as −Σ J^T F.
  const OracleVec id = o.inverse_dynamics(q, qd, qdd);
  worst_algebra = std::max(worst_algebra, relative(id, M * qdd + o.bias(q, qd)));
  worst_algebra = std::max(worst_algebra, relative(o.inverse_dynamics(q, qd, qdd, ext), id - o.external_torque(q, ext)));
  worst_algebra = std::max(worst_algebra, relative(o.forward_dynamics(q, qd, id, {}), qdd));

  // The KKT solution satisfies the equations of motion and the constraint.
  for (std::size_t nc : {1u, 3u}) {
    test::RandomProblem local(static_cast<unsigned>(nc));
    OracleMat alpha(6, nc);
    for (std::size_t k = 0; k < nc; ++k) alpha.col(k) = test::to_six(local.unit_direction());
    const OracleVec beta = OracleVec::Random(nc);
    if (nc > n) continue;  // rank-deficient by construction: the KKT system has no unique solution
    const Oracle::KktSolution s = o.kkt(q, qd, tau, ext, c.chain.tip_link, alpha, beta);
    if (skips.skip(s.cond > kWellConditioned, "cond(E) > 1e6")) continue;
    const OracleVec lhs = M * s.qdd + o.bias(q, qd);
    const OracleVec rhs = tau + o.external_torque(q, ext) + o.jacobian(q, c.chain.tip_link).transpose() * alpha * s.nu;
    worst_algebra = std::max(worst_algebra, relative(lhs, rhs));
    worst_algebra = std::max(worst_algebra,
                             relative(OracleVec(alpha.transpose() * o.spatial_acceleration(q, qd, s.qdd, c.chain.tip_link)), beta));
  }
}

TEST(DenseOracle, AgreesWithFiniteDifferencesAndTheLagrangian) {
  test::RandomProblem random(11);
  double worst_fd = 0, worst_algebra = 0;
  // KKT identities are checked where cond(E) <= 1e6 (the algebra tolerance is flat): measured
  // none of 935 constrained solves beyond it.
  test::SkipCount skips("oracle KKT identities", 0.05);
  for (const auto& c : test::bundled_cases(true))
    for (int s = 0; s < test::state_count(50); ++s) check_oracle(c, random, worst_fd, worst_algebra, skips);
  test::RandomChainGenerator generator(12);
  for (int s = 0; s < test::state_count(300); ++s)
    check_oracle(test::random_case(generator), random, worst_fd, worst_algebra, skips);
  std::cout << "[oracle] max finite-difference error " << worst_fd << ", max algebraic error " << worst_algebra << "\n";
  RecordProperty("max_finite_difference_error", std::to_string(worst_fd));
  RecordProperty("max_algebraic_error", std::to_string(worst_algebra));
  EXPECT_LE(worst_fd, kFiniteDifferenceTolerance);
  EXPECT_LE(worst_algebra, kOracleAlgebraTolerance);
}

// ---------------------------------------------------------------------------------------------
// The reference solver against the KKT solution.

struct Worst {
  double qdd = 0, nu = 0, residual = 0;  // max errors where cond(E) <= 1e6
  double energy = 0;                     // E identity, all states
  double over_tolerance = 0;             // max error / its tolerance, all states
  LongDouble max_cond = 1;
  int states = 0, ill_conditioned = 0, rank_deficient = 0;
};

// One random state: the solver (double, policy original) against the oracle's KKT solve.
void compare_state(const test::OracleCase& c, solver::ReferenceSolver<double>& reference, std::size_t nc,
                   test::RandomProblem& random, Worst& worst, test::SkipCount& skips) {
  const std::vector<std::string> links = solver::direction_links(reference.model().layout, c.chain);
  const test::OracleProblem p = test::draw_problem(random, c, nc);
  const Oracle o(c.chain, p.base_gravity());
  const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::original);
  const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd), tau = test::to_long(p.tau_ff);
  const auto ext = p.oracle_wrenches(c);
  const OracleMat alpha = p.alpha(nc);
  const OracleVec beta = test::to_long(p.beta);
  std::string where = c.name + " Nc=" + std::to_string(nc);
  for (const auto& line : solver::constraint_set_summary(reference.model().layout)) where += "; " + line;
  ++worst.states;

  // E^A_cstr,0 = Jc M^-1 Jc^T, Jc = (α_k^T J_link(k))_k.
  const OracleMat Jc = o.constraint_jacobian(q, links, alpha);
  const OracleMat E = Oracle::constraint_energy(o.mass_matrix(q), Jc);
  if (nc > 0) {
    const Eigen::MatrixXd& E_solver = reference.articulated().body[0].constraint_energy;
    const double e = static_cast<double>((E_solver.cast<LongDouble>() - E).cwiseAbs().maxCoeff() /
                                         E.cwiseAbs().maxCoeff());
    worst.energy = std::max(worst.energy, e);
    EXPECT_LE(e, kEnergyTolerance) << where;
  }

  // The constraints the solver's pivot policy keeps: all of them unless E is singular to the
  // pivot tolerance (redundant directions: Nc > N, the planar robot's Nc = 6, prismatic-only
  // chains). The oracle solves for those; the dropped multipliers are 0.
  const auto kept = Oracle::kept_constraints(E, LongDouble(reference.model().pivot_tolerance));
  EXPECT_EQ(sol.dropped_pivots, static_cast<double>(nc - kept.size())) << where;
  if (kept.size() < nc) ++worst.rank_deficient;
  OracleMat alpha_kept(6, kept.size());
  OracleVec beta_kept(kept.size());
  std::vector<std::string> links_kept;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    alpha_kept.col(k) = alpha.col(kept[k]);
    beta_kept[k] = beta[kept[k]];
    links_kept.push_back(links[kept[k]]);
  }
  const Oracle::KktSolution kkt = o.kkt(q, qd, tau, ext, links_kept, alpha_kept, beta_kept);
  OracleVec nu = OracleVec::Zero(nc);
  for (std::size_t k = 0; k < kept.size(); ++k) nu[kept[k]] = kkt.nu[k];
  const bool well_conditioned = kkt.cond <= kWellConditioned;
  worst.max_cond = std::max(worst.max_cond, kkt.cond);
  if (!well_conditioned) ++worst.ill_conditioned;
  const std::string cond = " cond(E)=" + std::to_string(static_cast<double>(kkt.cond));
  if (skips.skip(!judged(kkt.cond), "cond(E) > 1e9")) return;

  // (b) q̈ and ν.
  const double tolerance = scaled_tolerance(kAgreementTolerance, kkt.cond);
  const double e_qdd = test::relative_error(sol.qdd, o.in_solver_coordinates(q, qd, kkt.qdd));
  const double e_nu = test::relative_error(sol.nu, nu);
  // τcmd = τff + Jc^T ν (T1): each direction's wrench acts where its set's link is.
  const double e_tau = test::relative_error(sol.tau_cmd, OracleVec(tau + Jc.transpose() * nu));
  EXPECT_LE(e_qdd, tolerance) << where << cond;
  EXPECT_LE(e_nu, tolerance) << where << cond;
  EXPECT_LE(e_tau, tolerance) << where << cond;
  worst.over_tolerance = std::max({worst.over_tolerance, e_qdd / tolerance, e_nu / tolerance, e_tau / tolerance});
  if (well_conditioned) {
    worst.qdd = std::max(worst.qdd, e_qdd);
    worst.nu = std::max(worst.nu, e_nu);
  }

  // (f) the kept constraints hold: α_k^T Ẍ_link(k) = β_k, with Ẍ_link the solver's own output
  // (set_acceleration of a listed set, else Ẍ_tip).
  if (!kept.empty()) {
    const auto& model = reference.model();
    OracleVec achieved(kept.size());
    LongDouble scale = std::max<LongDouble>(1, beta_kept.cwiseAbs().maxCoeff());
    for (std::size_t j = 0; j < kept.size(); ++j) {
      const std::size_t set = model.constraint_set_of[kept[j]];
      const Oracle::Six a = test::to_six(sol.set_acceleration.empty() ? sol.tip_acceleration : sol.set_acceleration[set]);
      achieved[j] = alpha_kept.col(j).dot(a);
      scale = std::max(scale, a.cwiseAbs().maxCoeff());
    }
    const double r = static_cast<double>((achieved - beta_kept).cwiseAbs().maxCoeff() / scale);
    const double residual_tolerance = scaled_tolerance(kResidualTolerance, kkt.cond);
    EXPECT_LE(r, residual_tolerance) << where << cond;
    worst.over_tolerance = std::max(worst.over_tolerance, r / residual_tolerance);
    if (well_conditioned) worst.residual = std::max(worst.residual, r);
  }
}

void report(const std::string& what, const Worst& w) {
  std::cout << "[" << what << "] " << w.states << " states, " << w.ill_conditioned << " with cond(E) > 1e6 (max "
            << static_cast<double>(w.max_cond) << "), " << w.rank_deficient
            << " with dropped pivots; where cond(E) <= 1e6, max relative error: qdd " << w.qdd << ", nu " << w.nu
            << ", residual " << w.residual << "; E identity " << w.energy << "; max error/tolerance "
            << w.over_tolerance << "\n";
  ::testing::Test::RecordProperty(what + "_max_qdd_error", std::to_string(w.qdd));
  ::testing::Test::RecordProperty(what + "_max_nu_error", std::to_string(w.nu));
  ::testing::Test::RecordProperty(what + "_max_residual", std::to_string(w.residual));
  ::testing::Test::RecordProperty(what + "_max_energy_error", std::to_string(w.energy));
}

TEST(DenseOracle, ReferenceSolverMatchesKktOnBundledRobots) {
  test::RandomProblem random(21);
  Worst worst;
  // Random unit directions: E^A_cstr,0 beyond cond 1e9 in few states (measured: 141 of 16000, 0.9%).
  test::SkipCount skips("dense oracle, bundled robots", 0.05);
  for (const auto& c : test::bundled_cases(true))
    for (std::size_t nc : {0u, 1u, 3u, 6u}) {
      solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
      for (int s = 0; s < test::state_count(1000); ++s) compare_state(c, reference, nc, random, worst, skips);
    }
  report("bundled", worst);
}

TEST(DenseOracle, ReferenceSolverMatchesKktOnRandomChains) {
  test::RandomProblem random(31);
  test::RandomChainGenerator generator(32);
  Worst worst;
  // Random chains (1-8 joints, any axes): E^A_cstr,0 beyond cond 1e9 in few states (measured: 3 of 4000).
  test::SkipCount skips("dense oracle, random chains", 0.05);
  for (int k = 0; k < test::state_count(1000); ++k) {
    const test::OracleCase c = test::random_case(generator);
    for (std::size_t nc : {0u, 1u, 3u, 6u}) {
      solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
      compare_state(c, reference, nc, random, worst, skips);
    }
  }
  report("random_chains", worst);
}

// Constraint sets on random links of the chain (1 to 3 sets, 1 to 6 directions each), drawn
// until they do not over-determine it (a scene would refuse those): the layout's sets, with
// every direction at run time.
// Every other constrained state forms the constraint rows outward (I6) instead of through the
// columns (I2): both formulations against the same oracle (the generator emits either). Every
// other pair runs without the refinement (R1): its second pass corrects any error on the setpoint
// side of E ν = … exactly (the solve is linear there), so a dropped bias term of (I5)/(I6) would
// otherwise go unseen (fault outward_bias_energy_dropped, tests/faults/faults.txt).
solver::SolverOptions rows_of_state(int k) {
  solver::SolverOptions options;
  options.constraint_rows = k % 2 == 0 ? solver::ConstraintRows::inward_columns : solver::ConstraintRows::outward_rows;
  options.refinement = k % 4 < 2;
  return options;
}

solver::DriverLayout random_sets_layout(const test::OracleCase& c, test::RandomProblem& random) {
  std::vector<std::string> moving;
  for (const auto& [link, frame] : c.chain.frames)
    if (frame.body > 0) moving.push_back(link);
  solver::DriverLayout layout = test::oracle_layout(c, 0);
  while (true) {
    std::vector<solver::ConstraintSet> sets;
    const int count = 1 + static_cast<int>(random.uniform(0, 3)) % 3;
    for (int k = 0; k < count; ++k) {
      const std::string& link = moving[static_cast<std::size_t>(random.uniform(0, 1) * moving.size()) % moving.size()];
      const bool taken = std::any_of(sets.begin(), sets.end(), [&](const auto& set) { return set.link == link; });
      if (!taken) sets.push_back(solver::ConstraintSet::on(link, 1 + static_cast<std::size_t>(random.uniform(0, 6)) % 6));
    }
    if (!solver::structurally_overdetermined(sets, c.chain).empty()) continue;
    layout.sets = sets;
    layout.constraints = 0;
    for (const auto& set : sets) layout.constraints += set.count;
    return layout;
  }
}

// Sets on any links: the coupled constraint-space system over all sets (I2 with each set's own
// columns, T1 with each set's wrench) against the KKT system with each direction's own link
// Jacobian, under the same tolerances as the tip-only tests above.
TEST(DenseOracle, ReferenceSolverMatchesKktWithConstraintSetsOnAnyLinks) {
  test::RandomProblem random(41);
  test::RandomChainGenerator generator(42);
  Worst worst;
  // Random sets on random links: E^A_cstr,0 beyond cond 1e9 in few states (measured: 4 of 1000).
  test::SkipCount skips("dense oracle, constraint sets on any links", 0.05);
  std::size_t listed = 0, off_tip = 0;
  const std::vector<test::OracleCase> bundled = test::bundled_cases(false);
  for (int k = 0; k < test::state_count(1000); ++k) {
    const test::OracleCase c =
        k % 4 == 0 ? bundled.at(static_cast<std::size_t>(k / 4) % bundled.size()) : test::random_case(generator);
    const solver::DriverLayout layout = random_sets_layout(c, random);
    listed += layout.sets.size();
    for (const auto& set : layout.sets) off_tip += c.chain.frames.at(set.link).body != c.chain.dof() ? 1 : 0;
    solver::ReferenceSolver<double> reference(c.chain, layout, rows_of_state(k));
    compare_state(c, reference, layout.constraints, random, worst, skips);
  }
  std::cout << "[sets] " << listed << " sets, " << off_tip << " of them on links short of the last body\n";
  EXPECT_GE(off_tip, listed / 4) << "the draw should put many sets short of the tip";
  report("constraint_sets", worst);
}

// A bundled robot's tree (the paths from `root` to each of `tips`), forces on the root link and
// the last tip.
test::OracleCase bundled_tree(const std::string& urdf, const std::string& root, const std::vector<std::string>& tips,
                              bool floating_base) {
  test::OracleCase c{urdf, test::load_tree(urdf, root, tips, floating_base), {}};
  c.external_links = {floating_base ? root : tips.front(), tips.back()};
  return c;
}

// Random trees (2 to 12 joints, each body on a random earlier one: chains, stars and everything
// between) and, every fifth case, the bundled dual Panda or the Panda to its two fingers (the
// second a <mimic> of the first, a joint of its own); Nc = 0 and constraint sets on random
// links of any branches: the same equations over λ(i), against the KKT system whose Jacobians and
// inverse dynamics walk the tree on their own.
TEST(DenseOracle, ReferenceSolverMatchesKktOnRandomTrees) {
  test::RandomProblem random(51);
  test::RandomChainGenerator generator(52);
  Worst worst;
  // Measured: 0 of 2000 states beyond cond 1e9 (4 beyond 1e6).
  test::SkipCount skips("dense oracle, random trees", 0.05);
  std::size_t branched = 0, sets_on_two_branches = 0;
  const test::OracleCase dual_panda =
      bundled_tree("robots/dual_panda/dual_panda.urdf", "station", {"left_panda_hand", "right_panda_hand"}, false);
  const test::OracleCase gripper = bundled_tree("robots/mobile_panda_gripper/mobile_panda_gripper.urdf", "mobile_base",
                                                {"panda_leftfinger", "panda_rightfinger"}, false);
  for (int k = 0; k < test::state_count(1000); ++k) {
    const test::OracleCase c = k % 10 == 0 ? dual_panda : k % 10 == 5 ? gripper : test::random_case(generator, true);
    branched += c.chain.is_chain() ? 0 : 1;
    solver::ReferenceSolver<double> free(c.chain, test::oracle_layout(c, 0));
    compare_state(c, free, 0, random, worst, skips);
    const solver::DriverLayout layout = random_sets_layout(c, random);
    for (std::size_t a = 0; a < layout.sets.size(); ++a)
      for (std::size_t b = a + 1; b < layout.sets.size(); ++b) {
        const std::size_t x = c.chain.frames.at(layout.sets[a].link).body, y = c.chain.frames.at(layout.sets[b].link).body;
        if (!c.chain.supports(x, y) && !c.chain.supports(y, x)) ++sets_on_two_branches;
      }
    solver::ReferenceSolver<double> constrained(c.chain, layout, rows_of_state(k));
    compare_state(c, constrained, layout.constraints, random, worst, skips);
  }
  std::cout << "[trees] " << branched << " branched trees, " << sets_on_two_branches
            << " pairs of constraint sets on different branches\n";
  EXPECT_GE(branched, static_cast<std::size_t>(test::state_count(1000)) / 2) << "the draw should mostly branch";
  EXPECT_GT(sets_on_two_branches, 0u);
  report("random_trees", worst);
}

// Floating bases (F5): the bundled quadruped (four feet), mobile Panda and mobile Panda to its two
// fingers (one a <mimic> of the other), and random trees on a
// random free root body, Nc = 0 and random constraint sets, against the KKT system of the oracle,
// which takes the base's six coordinates as ordinary joints at 0 (with their velocity-product
// terms; in_solver_coordinates turns its q̈ into the base's spatial acceleration).
TEST(DenseOracle, ReferenceSolverMatchesKktOnFloatingBases) {
  test::RandomProblem random(61);
  test::RandomChainGenerator generator(62);
  Worst worst;
  // Measured: 0 of 2000 states beyond cond 1e9.
  test::SkipCount skips("dense oracle, floating bases", 0.05);
  const std::vector<test::OracleCase> bundled = {
      bundled_tree("robots/quadruped/quadruped.urdf", "trunk", {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, true),
      bundled_tree("robots/mobile_panda/mobile_panda.urdf", "mobile_base", {"panda_hand"}, true),
      // A tree to Franka's two fingers, the second a <mimic> of the first: a joint of its own.
      bundled_tree("robots/mobile_panda_gripper/mobile_panda_gripper.urdf", "mobile_base",
                   {"panda_leftfinger", "panda_rightfinger"}, true)};
  for (int k = 0; k < test::state_count(1000); ++k) {
    const test::OracleCase c =
        k % 4 == 0 ? bundled.at(static_cast<std::size_t>(k / 4) % bundled.size()) : test::random_case(generator, false, true);
    ASSERT_TRUE(c.chain.floating_base);
    solver::ReferenceSolver<double> free(c.chain, test::oracle_layout(c, 0));
    compare_state(c, free, 0, random, worst, skips);
    const solver::DriverLayout layout = random_sets_layout(c, random);
    solver::ReferenceSolver<double> constrained(c.chain, layout, rows_of_state(k));
    compare_state(c, constrained, layout.constraints, random, worst, skips);
  }
  report("floating_bases", worst);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
