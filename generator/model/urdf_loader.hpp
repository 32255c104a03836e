// Reads a serial chain, or the tree of several root-to-tip paths, out of a URDF file (urdfdom)
// and validates it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "model/chain.hpp"

namespace sweepgen::model {

struct ChainSpec {
  std::string urdf;       // path of the URDF file
  std::string root_link;  // empty: the URDF's root link
  std::string tip_link;   // empty: the deepest link, if the tree below the root is a single chain
  std::map<std::string, double> rotor_inertia;  // d_i by joint name (URDF has no such element)
  std::string rotor_inertia_source = "--rotor-inertia";  // where those values came from, for messages
  // Positions [rad or m] at which moving joints off the chain are locked, by joint name; joints
  // not listed are locked at 0 clamped into their limits. `locked_joint_locations` names where
  // each entry came from ("file:line:column"), for messages; "command line" when absent.
  std::map<std::string, double> locked_joints;
  std::map<std::string, std::string> locked_joint_locations;
  std::vector<std::string> branch_tips;  // further tips: the tree of all root-to-tip paths (Chain)
  bool floating_base = false;  // the root link moves freely (Chain::floating_base, F5)
};

// Reads and validates the chain, lumping every link that a moving body carries (chain.hpp).
// Throws InputError naming the file, element and reason on anything invalid, including a last
// joint that cannot accelerate (D_N = 0), a locked position that names no off-chain moving joint
// or lies outside its limits, and an off-chain joint that cannot be locked (floating, planar, or
// a mimic of a chain joint).
Chain load_chain(const ChainSpec& spec);

// Rotation matrix of URDF roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll)). Angles within
// 1e-10 rad of a multiple of pi/2 are taken as exactly that multiple, so that such rotations
// are exact permutations with signs (they fold away in generated code).
Mat3 rotation_from_rpy(double roll, double pitch, double yaw);

}  // namespace sweepgen::model
