// The consumer project's program: one state through the generated solver's structured API
// (outward, decompose, solve_original) and its flat entry point; checks that the results are
// finite and that both paths agree exactly (they run the same code); then the state five times
// through the batch entry point, which must give the flat call's values bit for bit in the widest
// lanes the CPU runs (sweepgen_add_solver without ARCH on x86-64: eight doubles with AVX-512, four
// with AVX2). Exit code 0 on success.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "planar_arm_solver.hpp"

namespace solver = planar_arm::f64;
using planar_arm::constraints;
using planar_arm::dof;

static_assert(dof == 3, "the planar arm has three moving joints");
static_assert(constraints == 2, "README.md's first scene fixes two constraint directions");
// in = [q, qd, tau_ff, tool_load, beta], out = [qdd, tau_cmd, tau_ctrl, nu, tip_acceleration, status]
static_assert(solver::flat_in_size == 3 * dof + 6 + constraints, "flat input layout");
static_assert(solver::flat_out_size == 3 * dof + constraints + 6 + 1, "flat output layout");

namespace {

int failures = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::printf("FAILED: %s\n", what);
    ++failures;
  }
}

bool all_finite(const double* values, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(values[i])) return false;
  return true;
}

bool all_equal(const double* a, const double* b, int n) {
  for (int i = 0; i < n; ++i)
    if (!(a[i] == b[i])) return false;
  return true;
}

}  // namespace

int main() {
  const double q[dof] = {0.3, 0.12, -0.7};
  const double qd[dof] = {0.5, -0.2, 1.1};
  const double beta[constraints] = {0.4, -1.5};
  solver::Drivers drivers{};
  const double tau_ff[dof] = {1.0, -2.0, 0.25};
  const double tool_load[6] = {0.0, 0.0, 0.1, 2.0, -1.0, 0.0};
  for (int i = 0; i < dof; ++i) drivers.tau_ff[i] = tau_ff[i];
  for (int i = 0; i < 6; ++i) drivers.tool_load[i] = tool_load[i];

  // Structured API.
  solver::State state;
  solver::outward(q, qd, state);
  solver::decompose(drivers, state);
  solver::Solution solution;
  solver::solve_original(state, beta, solution);

  // Flat API.
  double in[solver::flat_in_size];
  double* cursor = in;
  for (double v : q) *cursor++ = v;
  for (double v : qd) *cursor++ = v;
  for (double v : tau_ff) *cursor++ = v;
  for (double v : tool_load) *cursor++ = v;
  for (double v : beta) *cursor++ = v;
  check(cursor == in + solver::flat_in_size, "flat input filled");
  double out[solver::flat_out_size];
  solver::solve_original_flat(in, out);

  // drivers_from_flat reads the driver part of `in` back.
  const solver::Drivers flat_drivers = solver::drivers_from_flat(in + 2 * dof);
  check(all_equal(flat_drivers.tau_ff, drivers.tau_ff, dof) && all_equal(flat_drivers.tool_load, drivers.tool_load, 6),
        "drivers_from_flat returns the drivers");

  check(all_finite(solution.qdd, dof), "qdd finite");
  check(all_finite(solution.tau_cmd, dof), "tau_cmd finite");
  check(all_finite(solution.tau_ctrl, dof), "tau_ctrl finite");
  check(all_finite(solution.nu, constraints), "nu finite");
  check(all_finite(solution.tip_acceleration, 6), "tip_acceleration finite");
  check(solution.status == planar_arm::status_ok, "status ok");
  check(all_finite(out, solver::flat_out_size), "flat output finite");

  const double* flat = out;
  check(all_equal(flat, solution.qdd, dof), "flat qdd == structured qdd");
  flat += dof;
  check(all_equal(flat, solution.tau_cmd, dof), "flat tau_cmd == structured tau_cmd");
  flat += dof;
  check(all_equal(flat, solution.tau_ctrl, dof), "flat tau_ctrl == structured tau_ctrl");
  flat += dof;
  check(all_equal(flat, solution.nu, constraints), "flat nu == structured nu");
  flat += constraints;
  check(all_equal(flat, solution.tip_acceleration, 6), "flat tip_acceleration == structured tip_acceleration");
  flat += 6;
  check(*flat == static_cast<double>(solution.status), "flat status == structured status");

  // The constraint holds: the tip's linear x/y acceleration (directions [0,0,0,1,0,0] and
  // [0,0,0,0,1,0]) equals beta.
  check(std::fabs(solution.tip_acceleration[3] - beta[0]) < 1e-9 && std::fabs(solution.tip_acceleration[4] - beta[1]) < 1e-9,
        "tip acceleration along the constraint directions equals beta");

  // The batch entry point: the same state five times (a whole group of lanes and a partial one).
  constexpr int n = 5;
  double rows[solver::flat_in_size * n], batch_out[solver::flat_out_size * n];
  for (int k = 0; k < solver::flat_in_size; ++k)
    for (int s = 0; s < n; ++s) rows[k * n + s] = in[k];
  solver::solve_original_batch(n, rows, batch_out);
  bool same = true;
  for (int k = 0; k < solver::flat_out_size; ++k)
    for (int s = 0; s < n; ++s) same = same && std::memcmp(&batch_out[k * n + s], &out[k], sizeof(double)) == 0;
  check(same, "batch == flat, bit for bit");
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                    __builtin_cpu_supports("bmi2");
  const bool avx512 = avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
                      __builtin_cpu_supports("avx512vl");
  check(solver::batch_lanes() == (avx512 ? 8 : avx2 ? 4 : 1), "the batch in the widest lanes the CPU runs");
#endif
  std::printf("batch: %d doubles a vector\n", solver::batch_lanes());

  std::printf("qdd =");
  for (double v : solution.qdd) std::printf(" %.17g", v);
  std::printf("\n");
  if (failures != 0) {
    std::printf("%d check(s) failed\n", failures);
    return 1;
  }
  std::printf("consumer: OK\n");
  return 0;
}
