// The cases of the numerical-stability suite (docs/stability.md, "Cases and states"): the
// synthetic family (generator/family, written to a directory and loaded through the normal
// scene and URDF loaders) and the bundled scenes, each with the configuration where its six tip
// directions are singular. Shared by tests/test_stability.cpp and `sweepgen report --stability`.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "scene/scene.hpp"

namespace sweepgen::report {

struct StabilityCase {
  std::string name;
  scene::Scene scene;
  model::Chain chain;
  std::vector<double> singular_q;  // empty: none known
  bool heavy = false;
};

// Writes the family case `name` (URDF and scene) into `dir` and loads it like any scene.
// Throws InputError for an unknown name.
StabilityCase family_stability_case(const std::string& name, const std::filesystem::path& dir);

// A bundled scene (path relative to the source tree, e.g. robots/ur5/ur5_nc6.yaml), named after
// its solver. q = 0 is singular for the three arms (stretched; panda and iiwa: joints 1, 3, 5, 7
// on one line; UR5: elbow straight and wrist axes 4 and 6 aligned; the tests check it through
// cond(E^A_cstr,0)); the planar robot has none.
StabilityCase bundled_stability_case(const std::string& scene_file, const std::filesystem::path& source_dir);

// The bundled scenes of the suite: three arms with six constraint directions, the planar robot's two.
const std::vector<std::string>& bundled_stability_scenes();

}  // namespace sweepgen::report
