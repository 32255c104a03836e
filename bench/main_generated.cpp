// bench_generated: Google Benchmark cases for every generated solver variant of the bundled
// scenes (bench/README.md). Names: <scene>/<f64|f32>/full/<policy> (flat entry point:
// outward + decompose + solve), <scene>/<f64|f32>/decompose (outward + decompose),
// <scene>/<f64|f32>/resolve/<policy> (solve_<policy> only, new setpoints, decomposed state),
// <scene>/f64/derivatives/<policy> (derivatives_<policy>_flat, scenes with derivatives: true).
#include <algorithm>
#include <iostream>

#include "support/generated_variant.hpp"

int main(int argc, char** argv) {
  using namespace sweepgen::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  auto variants = generated_variants();
  std::sort(variants.begin(), variants.end(), [](const auto& a, const auto& b) { return a.id() < b.id(); });
  try {
    for (const auto& v : variants) {
      v.register_benchmarks(v, make_inputs(v.scene_path));
      if (v.register_derivative_benchmarks) v.register_derivative_benchmarks(v, make_inputs(v.scene_path));
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_generated: " << e.what() << "\n";
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
