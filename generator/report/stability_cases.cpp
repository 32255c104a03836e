#include "report/stability_cases.hpp"

#include "io/output_files.hpp"
#include "family/family.hpp"

namespace sweepgen::report {

StabilityCase family_stability_case(const std::string& name, const std::filesystem::path& dir) {
  const family::FamilyCase c = family::family_case(name);
  const std::string urdf = (dir / (name + ".urdf")).string(), scene_file = (dir / (name + ".yaml")).string();
  io::write_files_atomically({{urdf, family::urdf_text(c.robot)}, {scene_file, family::scene_text(c)}});
  StabilityCase s{name, scene::load_scene(scene_file), {}, c.singular_q, c.heavy};
  s.chain = scene::load_scene_chain(s.scene);
  return s;
}

StabilityCase bundled_stability_case(const std::string& scene_file, const std::filesystem::path& source_dir) {
  StabilityCase s{"", scene::load_scene((source_dir / scene_file).string()), {}, {}, false};
  s.name = s.scene.solver;
  s.chain = scene::load_scene_chain(s.scene);
  if (scene_file.find("planar") == std::string::npos) s.singular_q.assign(s.chain.dof(), 0.0);
  return s;
}

const std::vector<std::string>& bundled_stability_scenes() {
  static const std::vector<std::string> scenes = {"robots/panda/panda_nc6.yaml", "robots/iiwa14/iiwa14_nc6.yaml",
                                                  "robots/ur5/ur5_nc6.yaml", "robots/planar/planar_nc2.yaml"};
  return scenes;
}

}  // namespace sweepgen::report
