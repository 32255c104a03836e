// bench_kdl: KDL's ChainHdSolver_Vereshchagin::CartToJnt on the Panda, panda_link0 ->
// panda_link7, at Nc = 0, 3, 6 (bench/support/kdl_bench.hpp: random q, qd, tau, unit alpha,
// beta; wrenches on panda_link5 and panda_link7). Names: kdl/panda/nc<Nc>.
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "support/kdl_bench.hpp"

int main(int argc, char** argv) {
  using namespace sweepgen::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    for (unsigned nc : {0u, 3u, 6u}) {
      auto bench = std::make_shared<KdlBench>(nc);
      benchmark::RegisterBenchmark(("kdl/panda/nc" + std::to_string(nc)).c_str(), [bench](benchmark::State& st) {
        std::size_t i = 0;
        for (auto _ : st) {
          benchmark::DoNotOptimize(bench->call(i));
          benchmark::ClobberMemory();
          if (++i == bench->count()) i = 0;
        }
      });
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_kdl: " << e.what() << "\n";
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
