// A scene's generated solver compiled and loaded for a test (report/compiled_solver.hpp) with the
// system compiler, its progress lines unprinted.
#pragma once

#include <filesystem>

#include "report/compiled_solver.hpp"

namespace sweepgen::test {

inline report::CompiledSolver compile_scene(const scene::Scene& s, const model::Chain& chain,
                                            const std::filesystem::path& dir,
                                            report::Optimisation optimisation = report::Optimisation::checked) {
  const report::CompileProgress quiet{[](int, const std::string&) {}, [](const std::string&) {}};
  return report::compile_scene_solver(s, chain, dir, "c++", quiet, report::Isa::baseline, optimisation);
}

}  // namespace sweepgen::test
