// bench_kdl: KDL's ChainHdSolver_Vereshchagin::CartToJnt on the Panda (panda_link0 ->
// panda_link7) at Nc = 0, 3, 6, and on the iiwa 14 and the UR5 at Nc = 6
// (bench/support/kdl_bench.hpp: the random problems of each robot's Nc = 6 scene).
// Names: kdl/<robot>/nc<Nc>.
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "support/kdl_bench.hpp"

int main(int argc, char** argv) {
  using namespace sweepgen::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    for (const auto& [robot, nc] : kdl_cases()) {
      auto bench = std::make_shared<KdlBench>(robot, nc);
      benchmark::RegisterBenchmark(("kdl/" + robot + "/nc" + std::to_string(nc)).c_str(), [bench](benchmark::State& st) {
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
