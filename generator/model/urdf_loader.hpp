// Reads a serial chain, or the tree of several root-to-tip paths, out of a URDF file (urdfdom)
// and validates it.
#pragma once

#include <map>
#include <memory>
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
  // Positions [rad or m] at which moving joints off the chain, or <mimic> joints on it, are locked,
  // by joint name; joints off the chain not listed are locked at 0 clamped into their limits. `locked_joint_locations` names where
  // each entry came from ("file:line:column"), for messages; "command line" when absent.
  std::map<std::string, double> locked_joints;
  std::map<std::string, std::string> locked_joint_locations;
  std::vector<std::string> branch_tips;  // further tips: the tree of all root-to-tip paths (Chain)
  bool floating_base = false;  // the root link moves freely (Chain::floating_base, F5)
  // The quarter-turn rule (model/quarter_turns.hpp): true takes URDF angles within 1e-10 rad of a
  // multiple of pi/2 as exactly that (each such origin listed in Chain::changes); false, literally.
  bool snap_quarter_turns = true;
  // The mimic mode: false ("independent", the default) takes each <mimic> joint as a joint of its
  // own; true ("coupled") holds each one the chain moves to its source exactly (Chain::couplings,
  // docs/derivation.md M1). `mimic_location` says where the mode came from, for messages.
  bool couple_mimics = false;
  std::string mimic_location = "--mimic coupled";
  // How the user names the tip, for the message when an empty tip_link cannot be found (the tree
  // branches): the scene's keys, or the command line's flags with the command that was run.
  std::string naming_the_tip = "the scene key 'tip' (for a tree, 'tips')";
  // The URDF's bytes once read (read_urdf), parsed in place of reading `urdf` again: a command
  // reads each input once, so that a pipe (--urdf <(cat r.urdf)) works and every step of the
  // command sees the same bytes. Null: load_chain reads `urdf` itself.
  std::shared_ptr<const std::string> urdf_bytes;
};

// The bytes of the URDF file at `path`, at most kMaxUrdfBytes of them (read_input_file).
std::shared_ptr<const std::string> read_urdf(const std::string& path);

// Reads and validates the chain, lumping every link that a moving body carries (chain.hpp).
// Throws InputError naming the file, element and reason on anything invalid, including a last
// joint that cannot accelerate (D_N = 0), a locked position that names no off-chain moving joint
// or <mimic> joint or lies outside its limits, an off-chain joint that cannot be locked (floating,
// planar) and a <mimic> of a joint the URDF does not have. A <mimic> joint is a joint of its own
// (Chain::mimics), or with couple_mimics held to its source (Chain::couplings; a source the chain
// does not move is refused); every number not taken as written is in Chain::changes.
Chain load_chain(const ChainSpec& spec);

}  // namespace sweepgen::model
