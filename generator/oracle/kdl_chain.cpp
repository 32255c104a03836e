#include "oracle/kdl_chain.hpp"

#ifdef SWEEPGEN_HAVE_KDL

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <kdl_parser/kdl_parser.hpp>
#include <set>

namespace sweepgen::oracle {
namespace {

// kdl_parser::treeFromFile with its console messages (e.g. "the root link has an inertia",
// irrelevant for a fixed base) held back, and shown only when it fails.
bool read_tree(const std::string& urdf, KDL::Tree& tree) {
  std::fflush(stderr);
  char path[] = "/tmp/sweepgen-kdl-parser-XXXXXX";
  const int capture = ::mkstemp(path);
  const int saved = capture >= 0 ? ::dup(2) : -1;
  if (saved >= 0) ::dup2(capture, 2);
  const bool ok = kdl_parser::treeFromFile(urdf, tree);
  if (saved >= 0) {
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
  }
  if (capture >= 0) {
    if (!ok) {
      std::ifstream in(path);
      std::cerr << in.rdbuf();
    }
    ::close(capture);
    ::unlink(path);
  }
  return ok;
}

// The inertia of every branch that leaves KDL's chain at `segment`, in that segment's frame, read
// from KDL's own tree: side links behind fixed joints, and behind moving joints held at the
// positions sweepgen locked them at (model::Chain::locked_joints), as sweepgen lumps them.
KDL::RigidBodyInertia off_chain_inertia(const KDL::Tree& tree, const std::string& segment,
                                        const std::set<std::string>& on_chain, const model::Chain& chain) {
  KDL::RigidBodyInertia sum = KDL::RigidBodyInertia::Zero();
  for (const auto& child : GetTreeElementChildren(tree.getSegment(segment)->second)) {
    const KDL::Segment& branch = GetTreeElementSegment(child->second);
    if (on_chain.count(branch.getName()) != 0) continue;
    double position = 0;
    for (const auto& locked : chain.locked_joints)
      if (locked.name == branch.getJoint().getName()) position = locked.position;
    sum = sum + branch.pose(position) *
                    (branch.getInertia() + off_chain_inertia(tree, branch.getName(), on_chain, chain));
  }
  return sum;
}

}  // namespace

// The KDL chain root -> last moving link, with the links behind fixed joints after it and every
// branch off the chain lumped into its segments' inertias (as sweepgen lumps them); false and
// the reason in `why` when the scene cannot be expressed.
bool kdl_chain(const std::string& urdf, const model::Chain& chain, KDL::Chain& out, std::string& why) {
  const std::size_t n = chain.dof();
  KDL::Tree tree;
  if (!read_tree(urdf, tree)) {
    why = "kdl_parser cannot read " + urdf;
    return false;
  }
  KDL::Chain parsed;
  if (!tree.getChain(chain.root_link, chain.tip_link, parsed)) {
    why = "KDL has no chain " + chain.root_link + " -> " + chain.tip_link;
    return false;
  }
  // Fixed joints are allowed only after the last moving one.
  unsigned moving = 0;
  for (unsigned i = 0; i < parsed.getNrOfSegments(); ++i) {
    const bool fixed = parsed.getSegment(i).getJoint().getType() == KDL::Joint::None;
    if (fixed && moving < n) {
      why = "not expressible: KDL's Vereshchagin solver cannot take fixed joints, and " +
            parsed.getSegment(i).getJoint().getName() + " is fixed before the last moving joint";
      if (moving == 0) {  // fixed joints above the first moving one: a root below them leaves them out
        unsigned last_fixed = i;
        while (last_fixed + 1 < parsed.getNrOfSegments() &&
               parsed.getSegment(last_fixed + 1).getJoint().getType() == KDL::Joint::None)
          ++last_fixed;
        why += "; root: " + parsed.getSegment(last_fixed).getName() + " (the scene key), the link the first moving "
               "joint hangs on, is expressible";
      }
      return false;
    }
    if (!fixed) {
      if (parsed.getSegment(i).getName() != chain.bodies[moving + 1].link) {
        why = "not expressible: KDL segment " + parsed.getSegment(i).getName() + " is not body " +
              std::to_string(moving + 1) + " (" + chain.bodies[moving + 1].link + ")";
        return false;
      }
      ++moving;
    }
  }
  if (moving != n || chain.tip().body != n) {
    why = "not expressible: KDL's chain has " + std::to_string(moving) + " moving joints, sweepgen's " + std::to_string(n);
    return false;
  }
  std::set<std::string> on_chain;
  for (unsigned i = 0; i < parsed.getNrOfSegments(); ++i) on_chain.insert(parsed.getSegment(i).getName());
  const auto with_branches = [&](const KDL::Segment& segment) {
    return segment.getInertia() + off_chain_inertia(tree, segment.getName(), on_chain, chain);
  };
  // The links behind the fixed joints after body N, with their branches, in body N's frame.
  KDL::RigidBodyInertia lumped = KDL::RigidBodyInertia::Zero();
  KDL::Frame behind = KDL::Frame::Identity();
  for (unsigned i = static_cast<unsigned>(n); i < parsed.getNrOfSegments(); ++i) {
    behind = behind * parsed.getSegment(i).getFrameToTip();
    lumped = lumped + behind * with_branches(parsed.getSegment(i));
  }
  for (unsigned i = 0; i < n; ++i) {
    const KDL::Segment& segment = parsed.getSegment(i);
    const KDL::Joint& joint = segment.getJoint();
    // Rotor inertia d_i as KDL joint inertia (added to D_i the same way).
    const double d = chain.joints[i + 1].rotor_inertia;
    const KDL::Joint with_rotor = d == 0 ? joint
                                         : KDL::Joint(joint.getName(), joint.JointOrigin(), joint.JointAxis(),
                                                      joint.getType(), 1, 0, d);
    const KDL::RigidBodyInertia inertia = i + 1 == n ? with_branches(segment) + lumped : with_branches(segment);
    out.addSegment(KDL::Segment(segment.getName(), with_rotor, segment.getFrameToTip(), inertia));
  }
  return true;
}

}  // namespace sweepgen::oracle

#endif  // SWEEPGEN_HAVE_KDL
