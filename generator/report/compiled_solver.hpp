// Steps 1–3 of `sweepgen report` (plain and --stability): a scene's generated solver (every policy
// of the scene in double, the original one in float too) written with a C wrapper, compiled by the
// system compiler into a shared library and loaded into this process.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "report/measure.hpp"
#include "report/native_library.hpp"
#include "scene/scene.hpp"

namespace sweepgen::report {

// The scene as the report measures it: in double and float, with `policies` (original first: the
// float entry point is the original policy's), returning every result (scene key outputs).
scene::Scene report_scene(scene::Scene s, std::vector<solver::Policy> policies = {solver::Policy::original});

// What each step says as it starts: `step` 1 generate, 2 compile, 3 load; `detail` for results.
struct CompileProgress {
  std::function<void(int step, const std::string& what)> step;
  std::function<void(const std::string& what)> detail;
};

struct CompiledSolver {
  std::vector<std::string> command;  // the compile command, for the record
  bool reused = false;               // the library in build_dir was already built from the same sources and command
  std::unique_ptr<SharedLibrary> library;
  std::map<solver::Policy, FlatSolve<double>> solve_f64_of;  // every policy of the scene
  // The generator's operation count of one full solve (outward + decompose + solve), by scalar
  // name ("double", "float") and policy: what the generated header lists.
  std::map<std::pair<std::string, solver::Policy>, std::size_t> operations;
  solver::ConstraintRows constraint_rows = solver::ConstraintRows::inward_columns;  // the generator's (I2) or (I6)
  FlatSolve<float> solve_f32 = nullptr;                      // policy original (null for a scene without float)
  // derivatives_<policy>_flat in double, each differentiable policy of a scene with derivatives.
  std::map<solver::Policy, FlatSolve<double>> derivatives_f64_of;
};

// Generates `s` (a report_scene, or one in double alone) into `build_dir`, compiles it with `cxx` for `isa`
// (and `optimisation`, report/native_library.hpp) and loads it.
// When build_dir already holds a library built from byte-identical sources with the same
// command, it is loaded as it is (a rerun of the report does not recompile). Throws io::IoError
// when the compiler cannot be run or fails (its output in build_dir/compile.log), dlopen()
// fails, or the library's flat sizes do not match the scene.
CompiledSolver compile_scene_solver(const scene::Scene& s, const model::Chain& chain,
                                    const std::filesystem::path& build_dir, const std::string& cxx,
                                    const CompileProgress& progress, Isa isa = Isa::baseline,
                                    Optimisation optimisation = Optimisation::deployed);

}  // namespace sweepgen::report
