// The kinematic tree that every sweep runs on: bodies 0..N, body 0 the fixed base (the root
// link's frame), joint i moving body i relative to its parent body λ(i) < i (`parent`; i-1 on a
// chain). The bodies are the moving joints on the paths from the root to the tip link and to
// each further tip (`branch_tips`): one path is a chain, several span a tree, numbered tip by
// tip, each path's new bodies root to tip. Every link of the URDF that a
// moving body carries rigidly is lumped into it: links behind fixed joints, on the chain or in
// a side branch (a gripper, a sensor), and links behind moving joints off the chain, which are
// locked at a position (ChainSpec::locked_joints, else 0 clamped into the joint's limits).
// Their frames stay addressable through `frames` (external forces, the tip/constraint frame).
// Links the chain does not carry (fixed to the base, or not below the root) are listed in
// `left_out`: nothing of the URDF vanishes unsaid.
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "spatial/spatial.hpp"

namespace sweepgen::model {

using Vec3 = spatial::Vec3<double>;
using Mat3 = spatial::Mat3<double>;
using Transform = spatial::Transform<double>;
using Inertia = spatial::Inertia<double>;

enum class JointType { revolute, prismatic };

struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  bool continuous = false;
  Vec3 axis = Vec3::UnitZ();  // unit vector in the joint frame (= the child body frame)
  Transform tree_transform;   // X_T: motion transform from the parent body's frame to the joint frame
  double rotor_inertia = 0;   // d_i, armature reflected to the joint [kg m^2 or kg]
  double effort_limit = std::numeric_limits<double>::infinity();  // [N m or N]
  double velocity_limit = std::numeric_limits<double>::infinity();
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  // One of the six coordinates of a floating base (docs/derivation.md, F5): held at q = 0 (its
  // q is never read), without a velocity-product term (O2).
  bool floating_base_coordinate = false;
};

// A link merged into a body's inertia.
struct LumpedLink {
  std::string link;
  double mass = 0;          // [kg]
  std::string locked_joint; // the off-chain moving joint that was locked to carry it, or "" (fixed joints only)
};

// A moving joint off the chain, held at `position` so that the links behind it are rigid.
struct LockedJoint {
  std::string name;
  std::size_t body = 0;   // the body that carries it (0: the base; then it changes nothing)
  double position = 0;    // [rad or m]
  bool from_scene = false;  // given in ChainSpec::locked_joints; else the default
};

// A chain joint's URDF <dynamics>: joint damping and Coulomb friction are not part of the
// model (ACHD takes joint torques); an application adds them to tau_ff (e.g. −damping q̇).
struct UnmodelledDynamics {
  std::string joint;
  double damping = 0, friction = 0;
};

// A URDF <mimic>: `joint` is written to follow `source` as q = multiplier q_source + offset. By
// default the model takes it as a joint of its own, as KDL and the URDF dynamics readers do: a
// degree of freedom on the chain, locked like any joint off it, or locked where the scene's
// locked_joints names it; the coupling is the application's to enforce. With the mimic mode
// `coupled` (ChainSpec::couple_mimics) each such joint on the chain follows its source exactly
// (JointCoupling, docs/derivation.md M1).
struct MimicJoint {
  std::string joint, source;
  double multiplier = 1, offset = 0;
};

// A moving joint of the chain held to another by a coupled <mimic> (M1): q_joint = multiplier
// q_source + offset, q̇ and q̈ in the same ratio. `source` is the root of the <mimic>s it follows (a
// follows b follows c: c, the numbers composed), itself a moving joint that follows none; both are
// joint indices 1..N. `through` names the <mimic>s on the way, for messages.
struct JointCoupling {
  std::size_t joint = 0, source = 0;
  double multiplier = 1, offset = 0;
  std::vector<std::string> through;
};

// A number of the URDF that the model does not take as written (docs/derivation.md, F2, F3): an
// <origin> under the quarter-turn rule, an <axis> scaled to unit length, an inertia tensor made
// exactly symmetric. `sweepgen info`, `generate` and the generated header list each.
struct ModelChange {
  std::string element;   // "joint 'j' <origin>", "joint 'j' <axis>", "link 'l' <inertial>"
  std::string written;   // the value as read
  std::string taken_as;  // the value the model uses
  double deviation = 0;  // the size of the change, in `unit`
  std::string unit;      // "rad", "(1 - 1/|axis|)", "kg m^2"
};

// A link the chain does not carry, with why.
struct LeftOutLink {
  std::string link;
  double mass = 0;  // [kg]
  std::string reason;
};

struct Body {
  std::string link;                      // URDF link whose frame is the body frame
  std::vector<LumpedLink> lumped_links;  // links merged into this body, in the order added
  Inertia inertia;                       // M_i about the body frame origin, in the body frame
  double mass = 0;
};

// A URDF link's frame on the chain: rigidly attached to `body`, with `X` the motion
// transform from that body's frame to the link's frame.
struct Frame {
  std::size_t body = 0;
  Transform X;
};

// A frame's pose as a URDF <origin> gives it, xyz and rpy (roll, pitch, yaw about the fixed x, y, z
// axes: R = Rz(yaw) Ry(pitch) Rx(roll)), as the motion transform from the parent frame to it (F1).
Transform origin_transform(const Vec3& xyz, const Vec3& rpy);

// Whether body `ancestor` is `body` or lies on its path to the base, `parent` a tree's λ (λ(i) < i).
bool supports(const std::vector<std::size_t>& parent, std::size_t ancestor, std::size_t body);

struct Chain {
  std::string source;      // file the chain was read from, for messages
  std::string root_link;
  std::string tip_link;     // the tip; its frame is the solution's Ẍ_tip
  std::vector<std::string> branch_tips;  // further tips, each with its path from the root
  std::vector<Body> bodies;    // 0..N, bodies[0] is the base (a fixed one: its links and mass, for the listing; no inertia)
  std::vector<Joint> joints;   // 0..N, joints[0] is unused (the base does not move)
  std::vector<std::size_t> parent;  // 0..N, parent[i] < i the body joint i moves body i against; parent[0] = 0
  std::map<std::string, Frame> frames;  // every link on the chain, lumped ones included
  std::vector<LockedJoint> locked_joints;  // moving joints off the chain, URDF tree order
  std::vector<LeftOutLink> left_out;       // links not carried by the chain, by name
  std::vector<UnmodelledDynamics> unmodelled_dynamics;  // chain joints with URDF damping or friction
  std::vector<MimicJoint> mimics;        // <mimic> joints the chain moves or locks, URDF order of reading
  std::vector<JointCoupling> couplings;  // with the mimic mode `coupled`: the <mimic> joints it moves, in joint order
  std::vector<ModelChange> changes;      // numbers not taken as written, in the order read
  // Origins whose angles are the doubles nearest to multiples of pi/2 (kRoundingOfQuarterTurns),
  // taken exactly: counted, not listed one by one.
  std::size_t exact_quarter_turns = 0;
  // A floating base (F5): joints 1..6 are the base's coordinates (rotations about x, y, z, then
  // translations along x, y, z of the root link's frame), bodies 1..5 massless, body 6 the root
  // link; body 0 is the inertial frame that coincides with the root link's at this instant.
  bool floating_base = false;

  std::size_t dof() const { return bodies.size() - 1; }
  // The base's coordinates among the joints: 6 for a floating base, else 0.
  std::size_t base_coordinates() const { return floating_base ? 6 : 0; }
  // Whether every body hangs from the one before it (parent[i] == i - 1).
  bool is_chain() const;
  // Whether body `ancestor` is `body` or lies on its path to the base.
  bool supports(std::size_t ancestor, std::size_t body) const;
  const Frame& tip() const { return frames.at(tip_link); }
  // For messages: "the chain from 'root' to 'tip'", or with further tips "the tree from 'root' to
  // 'tip', 'a', 'b'" (every tip).
  std::string extent() const;
  // Index (1..N) of the joint named `name`, or 0 if there is none.
  std::size_t joint_index(const std::string& name) const;
  // The joints whose q and q̇ are inputs: every one but the coupled <mimic> joints (M1).
  std::size_t independent_dof() const { return dof() - couplings.size(); }
  // Joint i's coupling (1..N), or null where it follows no joint.
  const JointCoupling* coupling_of(std::size_t i) const;
};

// The coupling of joint i (1..N) among `couplings`, or null where it follows no joint.
const JointCoupling* coupling_of(const std::vector<JointCoupling>& couplings, std::size_t i);

// The names of a floating base's six coordinates, joints 1..6 (F5).
const std::vector<std::string>& floating_base_joint_names();

// Makes body 0 of `chain` (the root link, no other body yet) a floating base (F5): body 0 becomes
// the inertial frame where the root link is now, six coordinates with massless bodies follow,
// and body 6 is the root link with `root_inertia` (about its origin, its frame) and `root_mass`.
void add_floating_base(Chain& chain, const Inertia& root_inertia, double root_mass);

// What the chain made of the URDF, a line each, for `sweepgen info` and the generated header:
// per moving body its own link and mass and every link lumped into it (with its mass, and the
// locked joint it hangs behind), then each locked joint with its position, then each link left
// out with its mass and why. Masses in kg, positions in rad or m.
std::vector<std::string> lumping_summary(const Chain& chain);

}  // namespace sweepgen::model
