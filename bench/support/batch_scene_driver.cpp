// The flat loop against the batch entry point of one generated scene, as a default build links it
// (bench/batch_scene.sh; bench/README.md, "The default build"). SWEEPGEN_SCENE is the scene's
// namespace; the f64 variant's first policy (flat_solves[0], batch_solves[0]).
// Per state: the least thread CPU time of seven rounds over n states (argv[1], default 16 384; a
// round repeats them until 65 536 were solved) of uniform random inputs in [-1, 1] (every input:
// joint values, drivers, directions and setpoints), the batch in rows of states (value k of state
// s at in[k * n + s]), the flat calls on the same states.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "solver.hpp"

namespace {

namespace scene = SWEEPGEN_SCENE::f64;

double thread_seconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::stoul(argv[1]) : 16384, repeats = (65536 + n - 1) / n;
  constexpr std::size_t in_size = scene::flat_in_size, out_size = scene::flat_out_size;
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> rows(n * in_size), states(n * in_size), batch_out(n * out_size), flat_out(n * out_size);
  for (double& value : rows) value = uniform(random);
  for (std::size_t k = 0; k < in_size; ++k)
    for (std::size_t s = 0; s < n; ++s) states[s * in_size + k] = rows[k * n + s];
  const auto flat = scene::flat_solves[0].solve;
  const auto batch = scene::batch_solves[0].solve;
  double flat_seconds = 1e30, batch_seconds = 1e30;
  for (int round = 0; round < 7; ++round) {
    double start = thread_seconds();
    for (std::size_t r = 0; r < repeats; ++r)
      for (std::size_t s = 0; s < n; ++s) flat(&states[s * in_size], &flat_out[s * out_size]);
    flat_seconds = std::min(flat_seconds, thread_seconds() - start);
    start = thread_seconds();
    for (std::size_t r = 0; r < repeats; ++r) batch(static_cast<int>(n), rows.data(), batch_out.data());
    batch_seconds = std::min(batch_seconds, thread_seconds() - start);
  }
  const double solved = static_cast<double>(n * repeats);
  std::printf("%s: %zu states, %d a vector, flat %.1f ns, batch %.1f ns a state, flat / batch %.2f\n",
              scene::flat_solves[0].policy, n, scene::batch_lanes(), 1e9 * flat_seconds / solved, 1e9 * batch_seconds / solved,
              flat_seconds / batch_seconds);
  return 0;
}
