// Trajectory optimisation with Ipopt: the Panda moves its hand between two poses on a table plane
// with minimum effort, the generated solver (panda_plane.yaml) as the dynamics and its generated
// derivatives as the exact constraint Jacobian.
//
//   trajectory_optimisation OUT_DIR [--intervals N] [--finite-difference] [--derivative-test]
//                           [--plane-height Z] [--end-lift D] [--check]
//
// The plane: z = the start pose's hand height (or Z); both poses are moved onto it (the end pose
// from kEnd, along the height's gradient). The hand is kept on it by the dynamics, not by the NLP:
// the constraint direction alpha = [0; Rᵀ n] and the stabilising law beta (plane_dynamics.hpp),
// both functions of (q, q̇) whose exact Jacobians the example adds to the generated ones; so the
// discrete trajectory leaves the plane by the integrator's error, which --check bounds. The NLP:
// shooting_nlp.hpp. Ipopt's options: hessian_approximation limited-memory, tol and
// constr_viol_tol 1e-8, max_iter 500 (an ipopt.opt in the working directory adds to them).
// --finite-difference: Ipopt's finite-difference Jacobian (jacobian_approximation
// finite-difference-values) instead of the exact one, for bench/trajectory_optimisation.sh.
// --derivative-test: Ipopt's derivative_test first-order at the starting point.
// --end-lift D: the end pose D metres above the plane, a problem the constraint makes infeasible.
// --check: asserts the result (the dynamics and the end pose met, the torque limits, the hand on
// the plane, a force the table can give), each against its bound (check() derives them); a failed
// check exits 1.
// Writes OUT_DIR/trajectory.csv and OUT_DIR/trajectory.png (gnuplot: joint torques, the hand's
// height over the plane, the plane's force ν). Exit codes: 0 solved, 1 not solved or a check
// failed, 2 bad arguments, an OUT_DIR that cannot be made or a pose that cannot reach the plane, 3 the
// table or the figure not written.
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "shooting_nlp.hpp"
#include "trajectory_output.hpp"

using namespace trajopt;

namespace {

constexpr double kStart[kDof] = {0.0, -0.2, 0.0, -2.4, 0.0, 2.2, 0.7853981633974483};  // hand down, in front
constexpr double kEnd[kDof] = {0.8, 0.1, 0.0, -2.0, 0.0, 2.1, 0.7853981633974483};     // to the side, then projected

// The hand's height at q and its gradient along q (hand_kinematics.hpp, Dual).
double height_and_gradient(const double* q, double* gradient) {
  Dual q_dual[kDof], qd_dual[kDof];
  const double zero[kDof] = {};
  seed(q, zero, q_dual, qd_dual);
  const HandState<Dual> hand = hand_state(q_dual, qd_dual);
  for (int i = 0; i < kDof; ++i) gradient[i] = hand.p[2].d[i];
  return hand.p[2].v;
}

// Moves q to the plane z = height by Gauss-Newton steps along the height's gradient (minimum-norm
// steps); false where the hand cannot reach it from q (no step brings it within 1e-12 m), with the
// closest height reached.
bool project_onto_plane(double* q, double height, double& closest) {
  closest = 0;
  double best = INFINITY;
  for (int iteration = 0; iteration < 50; ++iteration) {
    double gradient[kDof];
    const double e = height_and_gradient(q, gradient) - height;
    if (std::fabs(e) < best) {
      best = std::fabs(e);
      closest = e + height;
    }
    if (std::fabs(e) < 1e-12) return true;
    double norm2 = 0;
    for (double g : gradient) norm2 += g * g;
    if (norm2 < 1e-12) return false;
    const double step = std::clamp(e / norm2, -0.5 / std::sqrt(norm2), 0.5 / std::sqrt(norm2));  // ≤ 0.5 rad
    for (int i = 0; i < kDof; ++i) q[i] -= step * gradient[i];
  }
  return false;
}

bool within_limits(const double* q) {
  for (int i = 0; i < kDof; ++i)
    if (q[i] < kQMin[i] || q[i] > kQMax[i]) return false;
  return true;
}

const char* status_name(Ipopt::SolverReturn status) {
  switch (status) {
    case Ipopt::SUCCESS: return "Solve_Succeeded";
    case Ipopt::MAXITER_EXCEEDED: return "Maximum_Iterations_Exceeded";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT: return "Solved_To_Acceptable_Level";
    case Ipopt::LOCAL_INFEASIBILITY: return "Infeasible_Problem_Detected";
    case Ipopt::RESTORATION_FAILURE: return "Restoration_Failed";
    case Ipopt::ERROR_IN_STEP_COMPUTATION: return "Error_In_Step_Computation";
    case Ipopt::INVALID_NUMBER_DETECTED: return "Invalid_Number_Detected";
    default: return "another Ipopt status (IpAlgTypes.hpp, SolverReturn)";
  }
}

struct Options {
  std::string out_dir;
  int intervals = 30;
  bool finite_difference = false;
  bool derivative_test = false;
  bool check = false;
  bool has_height = false;
  double height = 0;
  double end_lift = 0;
};

bool parse(int argc, char** argv, Options& o) {
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool has_value = a + 1 < argc;
    if (arg == "--finite-difference") o.finite_difference = true;
    else if (arg == "--derivative-test") o.derivative_test = true;
    else if (arg == "--check") o.check = true;
    else if (arg == "--intervals" && has_value) o.intervals = std::atoi(argv[++a]);
    else if (arg == "--plane-height" && has_value) o.has_height = true, o.height = std::atof(argv[++a]);
    else if (arg == "--end-lift" && has_value) o.end_lift = std::atof(argv[++a]);
    else if (!arg.empty() && arg[0] != '-' && o.out_dir.empty()) o.out_dir = arg;
    else return false;
  }
  return !o.out_dir.empty() && o.intervals >= 2;
}


// Sum of |e_k| of the discrete closed loop (semi-implicit Euler on ë = −kd ė − kp e) after a unit
// kick of the height at step 0: what a kick in every step adds up to at most.
double kick_gain(const Problem& problem) {
  const double h = problem.duration / problem.intervals;
  double e = 1, e_dot = 0, sum = 0;
  for (int k = 0; k < 100000 && (k < 10 || std::fabs(e) + std::fabs(e_dot) * h > 1e-17); ++k) {
    sum += std::fabs(e);
    e_dot += h * (-problem.law.kd * e_dot - problem.law.kp * e);
    e += h * e_dot;
  }
  return sum;
}

// --check: the solution meets the dynamics, the limits and the plane, each within its stated bound.
bool check(const Problem& problem, const std::vector<double>& x, const std::vector<Node>& nodes) {
  bool ok = true;
  auto report = [&](const char* what, double value, double bound) {
    const bool pass = value <= bound;
    std::printf("check: %-58s %.3g <= %.3g %s\n", what, value, bound, pass ? "ok" : "FAILED");
    ok = ok && pass;
  };
  // The defects, recomputed: Ipopt stops only when the unscaled constraint violation (max norm)
  // is at most constr_viol_tol = 1e-8; x_0 and x_N are fixed variables, so the last interval's
  // defect is the end pose being reached.
  const double h = problem.duration / problem.intervals;
  double defect = 0;
  for (int k = 0; k < problem.intervals; ++k) {
    const double* q = x.data() + ShootingNlp::state_index(k);
    const double* q_next = x.data() + ShootingNlp::state_index(k + 1);
    const DynamicsValue f = dynamics(problem.law, q, q + kDof, x.data() + ShootingNlp::torque_index(k));
    for (int i = 0; i < kDof; ++i) {
      const double qd_next = q[kDof + i] + h * f.qdd[i];
      defect = std::max({defect, std::fabs(q_next[kDof + i] - qd_next), std::fabs(q_next[i] - q[i] - h * qd_next)});
    }
  }
  report("max dynamics defect (end pose included) [rad, rad/s]", defect, 1e-8);
  // Ipopt keeps bounds within bound_relax_factor = 1e-8 of each (relative for |bound| > 1).
  double torque_ratio = 0;
  for (const Node& n : nodes)
    for (int i = 0; i < kDof; ++i) torque_ratio = std::max(torque_ratio, std::fabs(n.tau[i]) / kTauMax[i]);
  report("max |tau_i| / tau_max_i", torque_ratio, 1 + 1e-8);
  // The hand on the plane. The solve makes ë = −kd ė − kp e exact at every node; the step
  // q_{k+1} = q_k + h q̇_{k+1} then moves e by h ė_{k+1} plus what the step's curvature adds,
  // −h²/2 q̇ᵀ∇²e q̇ to leading order (e(q + h q̇) = e + h ė + h²/2 q̇ᵀ∇²e q̇, while ė_{k+1} already
  // carries h q̇ᵀ∇²e q̇ through ë): a kick d_k per step, which the closed loop sums with at most
  // kick_gain() (its impulse response's 1-norm). Twice that covers the O(h) terms past the leading
  // one; and 1 mm is the ceiling whatever the motion.
  double kick = 0, worst_height = 0;
  for (const Node& n : nodes) {
    kick = std::max(kick, 0.5 * h * h * std::fabs(n.height_curvature));
    worst_height = std::max(worst_height, std::fabs(n.height));
  }
  const double height_bound = 2 * kick_gain(problem) * kick;
  report("max |hand height over the plane| [m]", worst_height, height_bound);
  report("its bound 2 * kick_gain * max h^2/2 |qd' Hess(e) qd| [m]", height_bound, 1e-3);
  // The plane holds the hand both ways; a table only pushes (ν > 0: the wrench +α ν along +z), so
  // the motion is one a table allows where ν never goes negative.
  double pull = -INFINITY;
  for (const Node& n : nodes) pull = std::max(pull, -n.nu);
  report("max -nu (the table pulls where > 0) [N]", pull, 0);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) {
    std::fprintf(stderr,
                 "usage: %s OUT_DIR [--intervals N>=2] [--finite-difference] [--derivative-test] [--plane-height Z] "
                 "[--end-lift D] [--check]\n",
                 argv[0]);
    return 2;
  }
  std::error_code error;
  std::filesystem::create_directories(options.out_dir, error);
  if (error) {
    std::fprintf(stderr, "trajectory_optimisation: cannot create %s: %s\n", options.out_dir.c_str(),
                 error.message().c_str());
    return 2;
  }
  Problem problem{};
  problem.duration = 1.5;
  problem.intervals = options.intervals;
  // Critically damped at 10 rad/s: h ω = 0.5 at 30 intervals, well inside the semi-implicit Euler
  // step's stable range (h ω < 2).
  problem.law.kp = 100;
  problem.law.kd = 20;
  std::copy(kStart, kStart + kDof, problem.q_start);
  std::copy(kEnd, kEnd + kDof, problem.q_end);
  double gradient[kDof];
  problem.law.height = options.has_height ? options.height : height_and_gradient(kStart, gradient);
  for (double* q : {problem.q_start, problem.q_end}) {
    double closest;
    if (!project_onto_plane(q, problem.law.height, closest) || !within_limits(q)) {
      std::fprintf(stderr,
                   "trajectory_optimisation: the plane z = %g m is out of the hand's reach from the %s pose within "
                   "the joint limits (closest hand height reached: %g m)\n",
                   problem.law.height, q == problem.q_start ? "start" : "end", closest);
      return 2;
    }
  }
  if (options.end_lift != 0) {  // off the plane: the NLP has no feasible point
    if (!project_onto_plane(problem.q_end, problem.law.height + options.end_lift, *gradient)) {
      std::fprintf(stderr, "trajectory_optimisation: --end-lift %g: no end pose at that height\n", options.end_lift);
      return 2;
    }
  }

  Ipopt::SmartPtr<ShootingNlp> nlp = new ShootingNlp(problem);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetStringValue("hessian_approximation", "limited-memory");
  app->Options()->SetNumericValue("tol", 1e-8);
  app->Options()->SetNumericValue("constr_viol_tol", 1e-8);
  app->Options()->SetIntegerValue("max_iter", 500);
  app->Options()->SetIntegerValue("print_level", 4);
  if (options.finite_difference)
    app->Options()->SetStringValue("jacobian_approximation", "finite-difference-values");
  if (options.derivative_test) {
    app->Options()->SetStringValue("derivative_test", "first-order");
    app->Options()->SetStringValue("derivative_test_print_all", "no");
  }
  if (app->Initialize() != Ipopt::Solve_Succeeded) {
    std::fprintf(stderr, "trajectory_optimisation: Ipopt did not initialise\n");
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const Ipopt::ApplicationReturnStatus returned = app->OptimizeTNLP(nlp);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const int iterations = Ipopt::IsValid(app->Statistics()) ? app->Statistics()->IterationCount() : -1;
  std::printf("trajectory_optimisation: %s Jacobian, %d intervals: %s (%d) after %d iterations, %.3f s (CPU %.3f s); "
              "effort %.6g\n",
              options.finite_difference ? "finite-difference" : "exact", problem.intervals,
              status_name(nlp->status()), static_cast<int>(returned), iterations, seconds, cpu_seconds, nlp->effort());
  if (nlp->status() != Ipopt::SUCCESS) {
    std::fprintf(stderr, "trajectory_optimisation: Ipopt did not solve the problem: %s%s\n", status_name(nlp->status()),
                 options.end_lift != 0 ? " (the end pose is off the plane the hand is held on)" : "");
    return 1;
  }
  const std::vector<Node> nodes = nodes_of(problem, nlp->solution());
  if (options.check && !check(problem, nlp->solution(), nodes)) return 1;
  if (!write_trajectory(options.out_dir, nodes)) return 3;
  return 0;
}
