// The benchmark kernels of one generated solver variant (a scene's f64 or f32 namespace),
// instantiated by the per-scene sources that bench/CMakeLists.txt configures from
// scene_variants.cpp.in. Each variant registers itself in generated_variants(); with
// SWEEPGEN_BENCH_GBENCH defined (when Google Benchmark is installed) it also has the Google
// Benchmark cases that bench_generated runs.
//
// All inputs are prepared before any timed or counted loop: kStates flat inputs (cast to the
// variant's scalar), the same as Drivers structs, and kStates States after outward() +
// decompose() with other setpoints for the re-solves. The loops cycle through them.
#pragma once

#include <array>
#include <cstddef>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/inputs.hpp"

#ifdef SWEEPGEN_BENCH_GBENCH
#include <benchmark/benchmark.h>
#endif

// Describes the generated variant in namespace `ns` (e.g. panda_nc6::f64) as struct `Name`
// (the idea of SWEEPGEN_GENERATED_API in tests/support/generated_check.hpp, plus Drivers).
#define SWEEPGEN_BENCH_API(Name, ns)                                                             \
  struct Name {                                                                                  \
    using Scalar = ns::Scalar;                                                                   \
    using State = ns::State;                                                                     \
    using Solution = ns::Solution;                                                               \
    using Drivers = ns::Drivers;                                                                 \
    static constexpr const auto& solves = ns::solves;                                            \
    static constexpr const auto& flat_solves = ns::flat_solves;                                  \
    static constexpr const auto& batch_solves = ns::batch_solves;                                \
    static constexpr int flat_in_size = ns::flat_in_size;                                        \
    static constexpr int flat_out_size = ns::flat_out_size;                                      \
    static void outward(const Scalar* q, const Scalar* qd, State& s) noexcept { ns::outward(q, qd, s); } \
    static Drivers drivers_from_flat(const Scalar* in) noexcept { return ns::drivers_from_flat(in); } \
    static void decompose(const Drivers& d, State& s) noexcept { ns::decompose(d, s); }         \
  }

// The derivative functions of the variant in `ns` (scene key derivatives) as struct `Name`.
#define SWEEPGEN_BENCH_DERIVATIVES(Name, ns)                                                     \
  struct Name {                                                                                  \
    static constexpr const auto& solves = ns::derivative_solves;                                 \
    static constexpr const auto& batch_solves = ns::derivative_batch_solves;                     \
    static constexpr int flat_out_size = ns::derivative_flat_out_size;                           \
  }

namespace sweepgen::bench {

// derivatives: the flat derivatives_<policy>_flat (outward + decompose + solve, differentiated);
// batch, derivatives_batch: the same states through solve_<policy>_batch and
// derivatives_<policy>_batch, kStates at a time (a call of these modes is one state).
enum class Mode { full, decompose, resolve, derivatives, batch, derivatives_batch };

struct GeneratedVariant {
  std::string stem;        // scene file stem, e.g. panda_nc6
  std::string tag;         // f64 or f32
  std::string scene_path;  // the scene file
  std::vector<std::string> policies;
#ifdef SWEEPGEN_BENCH_GBENCH
  void (*register_benchmarks)(const GeneratedVariant&, const SceneInputs&);
  void (*register_derivative_benchmarks)(const GeneratedVariant&, const SceneInputs&) = nullptr;
#endif
  // Runs `calls` iterations of `mode` (policy index `policy`; ignored for decompose),
  // cycling through the prepared inputs; returns a checksum of the outputs.
  double (*run_calls)(const SceneInputs&, std::size_t policy, Mode mode, long calls);
  // The policies with a derivatives_<policy> function (scene key derivatives), and its mode
  // `derivatives`, which run_calls passes on to run_derivatives (policy indexes this list).
  std::vector<std::string> derivative_policies;
  double (*run_derivatives)(const SceneInputs&, std::size_t policy, long calls, bool batch) = nullptr;
  std::string id() const { return stem + "/" + tag; }
};

inline std::vector<GeneratedVariant>& generated_variants() {
  static std::vector<GeneratedVariant> variants;
  return variants;
}

template <class Api>
struct Prepared {
  using Scalar = typename Api::Scalar;
  std::size_t dof;
  std::vector<Scalar> flat;  // kStates * flat_in_size, contiguous
  std::vector<typename Api::Drivers> drivers;
  std::vector<typename Api::State> states;  // after outward + decompose
  std::vector<std::array<Scalar, 6>> new_beta;

  explicit Prepared(const SceneInputs& inputs) : dof(inputs.dof) {
    for (std::size_t i = 0; i < inputs.flat.size(); ++i) {
      const auto& in = inputs.flat[i];
      if (in.size() != static_cast<std::size_t>(Api::flat_in_size))
        throw std::logic_error("flat input size mismatch for " + inputs.scene.solver);
      const std::size_t base = flat.size();
      for (double v : in) flat.push_back(static_cast<Scalar>(v));
      drivers.push_back(Api::drivers_from_flat(flat.data() + base + 2 * dof));
      std::array<Scalar, 6> beta{};
      for (std::size_t k = 0; k < inputs.new_beta[i].size(); ++k) beta[k] = static_cast<Scalar>(inputs.new_beta[i][k]);
      new_beta.push_back(beta);
    }
    states.resize(inputs.flat.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
      Api::outward(in(i), in(i) + dof, states[i]);
      Api::decompose(drivers[i], states[i]);
    }
  }
  std::size_t count() const { return states.size(); }
  const Scalar* in(std::size_t i) const { return flat.data() + i * Api::flat_in_size; }
  // Every state's flat input in rows of count() values, as the batch entry points take them.
  std::vector<Scalar> rows() const {
    std::vector<Scalar> rows(flat.size());
    for (std::size_t i = 0; i < count(); ++i)
      for (int k = 0; k < Api::flat_in_size; ++k) rows[k * count() + i] = in(i)[k];
    return rows;
  }
};

// `states` states through a batch entry point `solve`, count() (kStates) at a time; `states` a
// multiple of it (count_instructions.sh rounds CALLS up), so every call solves the same states.
template <class Api>
double run_batches(const Prepared<Api>& p, void (*solve)(int, const typename Api::Scalar*, typename Api::Scalar*) noexcept,
                   int out_size, long states) {
  const auto count = static_cast<long>(p.count());
  if (states % count != 0) throw std::runtime_error("batch modes: N must be a multiple of " + std::to_string(count));
  const std::vector<typename Api::Scalar> in = p.rows();
  std::vector<typename Api::Scalar> out(static_cast<std::size_t>(count * out_size));
  double checksum = 0;
  for (long done = 0; done < states; done += count) {
    solve(static_cast<int>(count), in.data(), out.data());
    checksum += static_cast<double>(out[0]);
  }
  return checksum;
}

template <class Api>
double run_calls(const SceneInputs& inputs, std::size_t policy, Mode mode, long calls) {
  const Prepared<Api> p(inputs);
  const std::size_t count = p.count();
  double checksum = 0;
  std::size_t i = 0;
  switch (mode) {
    case Mode::full: {
      const auto solve = Api::flat_solves[policy].solve;
      std::array<typename Api::Scalar, Api::flat_out_size> out{};
      for (long c = 0; c < calls; ++c) {
        solve(p.in(i), out.data());
        checksum += static_cast<double>(out[0]);
        if (++i == count) i = 0;
      }
      break;
    }
    case Mode::decompose: {
      typename Api::State state{};
      for (long c = 0; c < calls; ++c) {
        Api::outward(p.in(i), p.in(i) + p.dof, state);
        Api::decompose(p.drivers[i], state);
        checksum += static_cast<double>(reinterpret_cast<const typename Api::Scalar*>(&state)[0]);
        if (++i == count) i = 0;
      }
      break;
    }
    case Mode::resolve: {
      const auto solve = Api::solves[policy].solve;
      typename Api::Solution out{};
      for (long c = 0; c < calls; ++c) {
        solve(p.states[i], p.new_beta[i].data(), out);
        checksum += static_cast<double>(out.qdd[0]);
        if (++i == count) i = 0;
      }
      break;
    }
    case Mode::batch: checksum = run_batches(p, Api::batch_solves[policy].solve, Api::flat_out_size, calls); break;
    case Mode::derivatives:
    case Mode::derivatives_batch: throw std::logic_error("derivatives: run_derivatives");
  }
  return checksum;
}

// `calls` flat derivative calls of policy index `policy`, as run_calls' full mode (`batch`: that
// many states through the batch entry point, as its batch mode).
template <class Api, class Derivatives>
double run_derivatives(const SceneInputs& inputs, std::size_t policy, long calls, bool batch) {
  const Prepared<Api> p(inputs);
  if (batch) return run_batches(p, Derivatives::batch_solves[policy].solve, Derivatives::flat_out_size, calls);
  const auto solve = Derivatives::solves[policy].solve_flat;
  std::vector<typename Api::Scalar> out(Derivatives::flat_out_size);
  double checksum = 0;
  std::size_t i = 0;
  for (long c = 0; c < calls; ++c) {
    solve(p.in(i), out.data());
    checksum += static_cast<double>(out[0]);
    if (++i == p.count()) i = 0;
  }
  return checksum;
}

#ifdef SWEEPGEN_BENCH_GBENCH
// Google Benchmark cases "<id>/derivatives/<policy>" of the flat derivative functions.
template <class Api, class Derivatives>
void register_derivatives(const GeneratedVariant& variant, const SceneInputs& inputs) {
  const auto p = std::make_shared<const Prepared<Api>>(inputs);
  for (std::size_t k = 0; k < std::size(Derivatives::solves); ++k) {
    benchmark::RegisterBenchmark((variant.id() + "/derivatives/" + Derivatives::solves[k].policy).c_str(),
                                 [p, k](benchmark::State& st) {
                                   const auto solve = Derivatives::solves[k].solve_flat;
                                   std::vector<typename Api::Scalar> out(Derivatives::flat_out_size);
                                   std::size_t i = 0;
                                   for (auto _ : st) {
                                     solve(p->in(i), out.data());
                                     benchmark::DoNotOptimize(out.data());
                                     benchmark::ClobberMemory();
                                     if (++i == p->count()) i = 0;
                                   }
                                 });
  }
}

template <class Api>
void register_generated(const GeneratedVariant& variant, const SceneInputs& inputs) {
  const auto p = std::make_shared<const Prepared<Api>>(inputs);
  const std::string prefix = variant.id() + "/";
  for (std::size_t k = 0; k < std::size(Api::flat_solves); ++k) {
    benchmark::RegisterBenchmark((prefix + "full/" + Api::flat_solves[k].policy).c_str(), [p, k](benchmark::State& st) {
      const auto solve = Api::flat_solves[k].solve;
      std::array<typename Api::Scalar, Api::flat_out_size> out{};
      std::size_t i = 0;
      for (auto _ : st) {
        solve(p->in(i), out.data());
        benchmark::DoNotOptimize(out);
        benchmark::ClobberMemory();
        if (++i == p->count()) i = 0;
      }
    });
  }
  for (std::size_t k = 0; k < std::size(Api::batch_solves); ++k) {
    // kStates states a batch: the rate counter is states per second (time per state = its inverse).
    benchmark::RegisterBenchmark((prefix + "batch/" + Api::batch_solves[k].policy).c_str(), [p, k](benchmark::State& st) {
      const auto solve = Api::batch_solves[k].solve;
      const std::vector<typename Api::Scalar> in = p->rows();
      std::vector<typename Api::Scalar> out(p->count() * Api::flat_out_size);
      for (auto _ : st) {
        solve(static_cast<int>(p->count()), in.data(), out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
      }
      st.counters["states"] = benchmark::Counter(static_cast<double>(st.iterations() * p->count()), benchmark::Counter::kIsRate);
    });
  }
  benchmark::RegisterBenchmark((prefix + "decompose").c_str(), [p](benchmark::State& st) {
    typename Api::State state{};
    std::size_t i = 0;
    for (auto _ : st) {
      Api::outward(p->in(i), p->in(i) + p->dof, state);
      Api::decompose(p->drivers[i], state);
      benchmark::DoNotOptimize(state);
      benchmark::ClobberMemory();
      if (++i == p->count()) i = 0;
    }
  });
  for (std::size_t k = 0; k < std::size(Api::solves); ++k) {
    benchmark::RegisterBenchmark((prefix + "resolve/" + Api::solves[k].policy).c_str(), [p, k](benchmark::State& st) {
      const auto solve = Api::solves[k].solve;
      typename Api::Solution out{};
      std::size_t i = 0;
      for (auto _ : st) {
        solve(p->states[i], p->new_beta[i].data(), out);
        benchmark::DoNotOptimize(out);
        benchmark::ClobberMemory();
        if (++i == p->count()) i = 0;
      }
    });
  }
}
#endif

// Adds the variant `Api` of the scene to generated_variants() (from a static initialiser).
template <class Api>
struct RegisterGenerated {
  RegisterGenerated(const char* stem, const char* tag, const char* scene_path) {
    GeneratedVariant v;
    v.stem = stem;
    v.tag = tag;
    v.scene_path = scene_path;
    for (const auto& s : Api::solves) v.policies.push_back(s.policy);
#ifdef SWEEPGEN_BENCH_GBENCH
    v.register_benchmarks = &register_generated<Api>;
#endif
    v.run_calls = &run_calls<Api>;
    generated_variants().push_back(std::move(v));
  }
};

// Adds the derivative functions `Derivatives` to the variant `stem`/`tag` registered before it
// (scene_variants.cpp.in: the same translation unit, in order).
template <class Api, class Derivatives>
struct RegisterDerivatives {
  RegisterDerivatives(const char* stem, const char* tag) {
    for (GeneratedVariant& v : generated_variants()) {
      if (v.stem != stem || v.tag != tag) continue;
      for (const auto& s : Derivatives::solves) v.derivative_policies.push_back(s.policy);
      v.run_derivatives = &run_derivatives<Api, Derivatives>;
#ifdef SWEEPGEN_BENCH_GBENCH
      v.register_derivative_benchmarks = &register_derivatives<Api, Derivatives>;
#endif
    }
  }
};

}  // namespace sweepgen::bench
