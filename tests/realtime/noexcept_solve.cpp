// The generated code needs no exceptions and no RTTI: this program and the bundled scenes'
// solver libraries (the panda_nc6 and iiwa14_nc6 ones here) are compiled with -fno-exceptions
// -fno-rtti -Wall -Wextra -Wpedantic -Werror (tests/CMakeLists.txt, "Hardening" block, and
// cmake/BundledScenes.cmake), and it runs a solve of every policy of both. No gtest: it would bring exceptions back. ctest runs it
// as realtime_no_exceptions; exit code 0 when every output is finite.
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
#error "built with exceptions: the -fno-exceptions flag did not reach this target"
#endif
#if defined(__GXX_RTTI) || defined(__cpp_rtti)
#error "built with RTTI: the -fno-rtti flag did not reach this target"
#endif

#include <cmath>
#include <cstdio>
#include <utility>

#include "iiwa14_nc6_solver.hpp"
#include "panda_nc6_solver.hpp"

namespace {

// A state of a 7-joint arm: positions inside both robots' limits, moderate velocities, a small
// feed-forward torque, one wrench per external-force driver, the six unit directions of the tip
// frame and gravity-compensating setpoints.
template <class Scalar, int InSize, int Dof, int Constraints>
void fill(Scalar (&in)[InSize]) {
  const double q[7] = {0.1, -0.5, 0.2, -2.0, 0.1, 1.8, 0.6};
  const double qd[7] = {0.3, -0.2, 0.1, 0.4, -0.1, 0.2, 0.5};
  int k = 0;
  for (int i = 0; i < Dof; ++i) in[k++] = static_cast<Scalar>(q[i]);
  for (int i = 0; i < Dof; ++i) in[k++] = static_cast<Scalar>(qd[i]);
  const int wrench_and_torque_values = InSize - 2 * Dof - 7 * Constraints;
  for (int i = 0; i < wrench_and_torque_values; ++i) in[k++] = static_cast<Scalar>(0.25 * ((i % 5) - 2));
  for (int c = 0; c < Constraints; ++c)
    for (int i = 0; i < 6; ++i) in[k++] = static_cast<Scalar>(i == c ? 1 : 0);
  for (int c = 0; c < Constraints; ++c) in[k++] = static_cast<Scalar>(c == 5 ? 9.81 : 0.0);
}

template <class Scalar, int N>
bool finite(const Scalar (&v)[N]) {
  for (int i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// Every flat solve, and the structured API on the same input, of one generated variant.
#define SWEEPGEN_RUN_VARIANT(scene, ns, label)                                                                 \
  [&]() -> bool {                                                                                       \
    static_assert(noexcept(ns::outward(nullptr, nullptr, std::declval<ns::State&>())), "noexcept");   \
    ns::Scalar in[ns::flat_in_size];                                                                   \
    fill<ns::Scalar, ns::flat_in_size, scene::dof, scene::constraints>(in);                                  \
    bool ok = true;                                                                                     \
    for (const auto& entry : ns::flat_solves) {                                                         \
      ns::Scalar out[ns::flat_out_size];                                                                \
      entry.solve(in, out);                                                                             \
      const bool good = finite(out);                                                                    \
      std::printf("%-24s %-20s qdd[0] = %+.6f  %s\n", label, entry.policy, static_cast<double>(out[0]), \
                  good ? "finite" : "NOT FINITE");                                                      \
      ok = ok && good;                                                                                  \
    }                                                                                                   \
    static ns::State state;                                                                             \
    ns::Solution solution;                                                                              \
    ns::outward(in, in + scene::dof, state);                                                               \
    ns::decompose(ns::drivers_from_flat(in + 2 * scene::dof), state);                                      \
    for (const auto& entry : ns::solves) {                                                              \
      entry.solve(state, in + ns::flat_in_size - scene::constraints, solution);                            \
      ok = ok && finite(solution.qdd) && finite(solution.tau_cmd) && finite(solution.nu);               \
    }                                                                                                   \
    return ok;                                                                                          \
  }()

}  // namespace

int main() {
  bool ok = true;
  ok = SWEEPGEN_RUN_VARIANT(panda_nc6, panda_nc6::f64, "panda_nc6::f64") && ok;
  ok = SWEEPGEN_RUN_VARIANT(panda_nc6, panda_nc6::f32, "panda_nc6::f32") && ok;
  ok = SWEEPGEN_RUN_VARIANT(iiwa14_nc6, iiwa14_nc6::f64, "iiwa14_nc6::f64") && ok;
  ok = SWEEPGEN_RUN_VARIANT(iiwa14_nc6, iiwa14_nc6::f32, "iiwa14_nc6::f32") && ok;
  std::printf("%s\n", ok ? "every solve finite (built with -fno-exceptions -fno-rtti)" : "FAILED");
  return ok ? 0 : 1;
}
