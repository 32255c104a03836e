// The robots under robots/, as the tests load them.
#pragma once

#include <string>
#include <vector>

#include "model/urdf_loader.hpp"

namespace sweepgen::test {

struct BundledRobot {
  std::string name;
  std::string urdf;              // relative to the source tree
  std::string root;
  std::string tip;               // default tip (may sit behind fixed joints)
  std::string last_moving_link;  // tip for oracles that cannot take fixed joints (KDL)
};

inline const std::vector<BundledRobot>& bundled_robots() {
  static const std::vector<BundledRobot> robots = {
      {"panda", "robots/panda/panda.urdf", "panda_link0", "panda_hand", "panda_link7"},
      {"iiwa14", "robots/iiwa14/iiwa14.urdf", "lbr_iiwa_link_0", "lbr_iiwa_link_ee", "lbr_iiwa_link_7"},
      {"ur5", "robots/ur5/ur5.urdf", "base_link", "tool0", "wrist_3_link"},
      {"planar", "robots/planar/planar_rpr.urdf", "base_link", "tool", "link3"},
  };
  return robots;
}

inline std::string source_path(const std::string& relative) { return std::string(SWEEPGEN_SOURCE_DIR) + "/" + relative; }

inline model::Chain load_bundled(const BundledRobot& robot, bool to_last_moving_link = false) {
  model::ChainSpec spec;
  spec.urdf = source_path(robot.urdf);
  spec.root_link = robot.root;
  spec.tip_link = to_last_moving_link ? robot.last_moving_link : robot.tip;
  return model::load_chain(spec);
}

// The tree of the paths from `root` to each of `tips` (the first is the chain's tip) of a URDF
// under robots/ (path relative to the source tree), on a fixed or a floating base.
inline model::Chain load_tree(const std::string& urdf, const std::string& root, const std::vector<std::string>& tips,
                              bool floating_base = false) {
  model::ChainSpec spec;
  spec.urdf = source_path(urdf);
  spec.root_link = root;
  spec.tip_link = tips.front();
  spec.branch_tips.assign(tips.begin() + 1, tips.end());
  spec.floating_base = floating_base;
  return model::load_chain(spec);
}

}  // namespace sweepgen::test
