// bench_reference: ReferenceSolver<double> (the generic solver the generator traces) on every
// bundled scene, full solve (outward + drivers + decompose + solve) with the original policy,
// on the same kStates random problems as bench_generated. Names: reference/<scene>/full/original.
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "support/reference_bench.hpp"
#include "support/scene_list.hpp"

int main(int argc, char** argv) {
  using namespace sweepgen::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    for (const auto& [stem, path] : bundled_scenes()) {
      auto bench = std::make_shared<ReferenceBench>(path);
      benchmark::RegisterBenchmark(("reference/" + stem + "/full/original").c_str(), [bench](benchmark::State& st) {
        std::size_t i = 0;
        for (auto _ : st) {
          const auto& solution = bench->full(i, sweepgen::solver::Policy::original);
          benchmark::DoNotOptimize(solution.qdd.data());
          benchmark::ClobberMemory();
          if (++i == bench->count()) i = 0;
        }
      });
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_reference: " << e.what() << "\n";
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
