// bench_calls: a minimal driver for instruction counting (bench/count_instructions.sh).
//
//   bench_calls --list
//   bench_calls <id> <policy> <N> [full|decompose|resolve|derivatives|batch|derivatives_batch]
//
// prepares the inputs of <id> (kStates random problems), then makes N calls, cycling through
// them, and prints a checksum. Running it under callgrind for N = 0 and N = 1000 and dividing
// the difference of the instruction counts by 1000 gives the instructions per call, without
// the set-up (scene and URDF parsing, input preparation). Ids:
//   <scene>/f64, <scene>/f32  generated solver (<scene> alone means f64); modes: full = flat
//                             solve_<policy>_flat (outward + decompose + solve), decompose =
//                             outward + decompose, resolve = solve_<policy> on a decomposed
//                             state with new setpoints, derivatives = the flat
//                             derivatives_<policy>_flat (scenes with derivatives: true); batch,
//                             derivatives_batch = N states through solve_<policy>_batch,
//                             derivatives_<policy>_batch, kStates (64) a call: N a multiple of 64
//   reference/<scene>         ReferenceSolver<double>; full or resolve
//   kdl/<robot>/nc<K>         KDL's ChainHdSolver_Vereshchagin (bench/support/kdl_bench.hpp:
//                             panda at K = 0, 3, 6; iiwa14, ur5 at K = 6; if built with KDL);
//                             policy ignored (pass "-"), mode full
//   dense_kkt/<scene>         the report's dense KKT solve (bench/support/dense_kkt_bench.hpp) on
//                             the trees, floating bases and panda_nc6; policy "-", mode full
// --list prints one line per id: "<id> <policy> <policy>..." ("kdl/<robot>/ncK -" for KDL);
// --list-derivatives one per generated variant with derivatives: "<id> <policy>...".
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <string>

#include "support/dense_kkt_bench.hpp"
#include "support/generated_variant.hpp"
#include "support/reference_bench.hpp"
#include "support/scene_list.hpp"
#ifdef SWEEPGEN_BENCH_HAVE_KDL
#include "support/kdl_bench.hpp"
#endif

namespace {

using namespace sweepgen::bench;

int usage() {
  std::cerr << "usage: bench_calls --list | --list-derivatives\n"
               "       bench_calls <id> <policy> <N> [full|decompose|resolve|derivatives|batch|derivatives_batch]\n";
  return 2;
}

int run(const std::string& id, const std::string& policy, long calls, Mode mode) {
  double checksum = 0;
  if (id.rfind("kdl/", 0) == 0) {
#ifdef SWEEPGEN_BENCH_HAVE_KDL
    if (mode != Mode::full) throw std::runtime_error("KDL: only mode full");
    const auto slash = id.find("/nc", 4);
    if (slash == std::string::npos) throw std::runtime_error("expected kdl/<robot>/nc<K>: " + id);
    KdlBench bench(id.substr(4, slash - 4), static_cast<unsigned>(std::stoul(id.substr(slash + 3))));
    for (long c = 0; c < calls; ++c) checksum += bench.call(static_cast<std::size_t>(c) % bench.count());
#else
    throw std::runtime_error("built without KDL");
#endif
  } else if (id.rfind("dense_kkt/", 0) == 0) {
    if (mode != Mode::full) throw std::runtime_error("dense KKT: only mode full");
    const std::string stem = id.substr(10);
    const auto scenes = bundled_scenes();
    const auto scene = std::find_if(scenes.begin(), scenes.end(), [&](const auto& s) { return s.first == stem; });
    if (scene == scenes.end()) throw std::runtime_error("no scene " + stem);
    const DenseKktBench bench(scene->second);
    for (long c = 0; c < calls; ++c) checksum += bench.call(static_cast<std::size_t>(c) % bench.count());
  } else if (id.rfind("reference/", 0) == 0) {
    const std::string stem = id.substr(10);
    const auto scenes = bundled_scenes();
    const auto scene = std::find_if(scenes.begin(), scenes.end(), [&](const auto& s) { return s.first == stem; });
    if (scene == scenes.end()) throw std::runtime_error("no scene " + stem);
    const auto p = sweepgen::solver::policy_from_name(policy);
    if (!p) throw std::runtime_error("no policy " + policy);
    ReferenceBench bench(scene->second);
    if (mode == Mode::resolve) {
      bench.decompose_all();
      for (long c = 0; c < calls; ++c) checksum += bench.resolve(static_cast<std::size_t>(c) % bench.count(), *p).qdd[0];
    } else if (mode == Mode::full) {
      for (long c = 0; c < calls; ++c) checksum += bench.full(static_cast<std::size_t>(c) % bench.count(), *p).qdd[0];
    } else {
      throw std::runtime_error("reference: modes full and resolve");
    }
  } else {
    const std::string full_id = id.find('/') == std::string::npos ? id + "/f64" : id;
    for (const auto& v : generated_variants()) {
      if (v.id() != full_id) continue;
      if (mode == Mode::derivatives || mode == Mode::derivatives_batch) {
        const auto d = std::find(v.derivative_policies.begin(), v.derivative_policies.end(), policy);
        if (d == v.derivative_policies.end()) throw std::runtime_error(full_id + " has no derivatives of policy " + policy);
        std::cout << v.run_derivatives(make_inputs(v.scene_path), static_cast<std::size_t>(d - v.derivative_policies.begin()), calls,
                                       mode == Mode::derivatives_batch)
                  << "\n";
        return 0;
      }
      const auto k = std::find(v.policies.begin(), v.policies.end(), policy);
      if (k == v.policies.end() && mode != Mode::decompose)
        throw std::runtime_error(full_id + " has no policy " + policy);
      const std::size_t index = k == v.policies.end() ? 0 : static_cast<std::size_t>(k - v.policies.begin());
      checksum = v.run_calls(make_inputs(v.scene_path), index, mode, calls);
      std::cout << checksum << "\n";
      return 0;
    }
    throw std::runtime_error("no generated variant " + full_id);
  }
  std::cout << checksum << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list") {
    auto variants = generated_variants();
    std::sort(variants.begin(), variants.end(), [](const auto& a, const auto& b) { return a.id() < b.id(); });
    for (const auto& v : variants) {
      std::cout << v.id();
      for (const auto& p : v.policies) std::cout << " " << p;
      std::cout << "\n";
    }
    for (const auto& [stem, path] : bundled_scenes()) {
      std::cout << "reference/" << stem << " original\n";
      if (counts_dense_kkt(make_inputs(path, 1))) std::cout << "dense_kkt/" << stem << " -\n";
    }
#ifdef SWEEPGEN_BENCH_HAVE_KDL
    for (const auto& [robot, nc] : kdl_cases()) std::cout << "kdl/" << robot << "/nc" << nc << " -\n";
#endif
    return 0;
  }
  if (argc == 2 && std::string(argv[1]) == "--list-derivatives") {
    for (const auto& v : generated_variants()) {
      if (v.derivative_policies.empty()) continue;
      std::cout << v.id();
      for (const auto& p : v.derivative_policies) std::cout << " " << p;
      std::cout << "\n";
    }
    return 0;
  }
  if (argc != 4 && argc != 5) return usage();
  Mode mode = Mode::full;
  if (argc == 5) {
    const std::string m = argv[4];
    if (m == "full") mode = Mode::full;
    else if (m == "decompose") mode = Mode::decompose;
    else if (m == "resolve") mode = Mode::resolve;
    else if (m == "derivatives") mode = Mode::derivatives;
    else if (m == "batch") mode = Mode::batch;
    else if (m == "derivatives_batch") mode = Mode::derivatives_batch;
    else return usage();
  }
  char* end = nullptr;
  const long calls = std::strtol(argv[3], &end, 10);
  if (*end != '\0' || calls < 0) return usage();
  try {
    return run(argv[1], argv[2], calls, mode);
  } catch (const std::exception& e) {
    std::cerr << "bench_calls: " << e.what() << "\n";
    return 1;
  }
}
