#include "model/urdf_loader.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "model/error.hpp"
#include "model/input_limits.hpp"
#include "model/mimic_couplings.hpp"
#include "model/xml_nesting.hpp"
#include "model/quarter_turns.hpp"
#include "model/xml_syntax.hpp"

namespace sweepgen::model {
namespace {

// Collects urdfdom's error messages so that they can be part of our error message. urdfdom
// logs some errors (an unparsable number in <inertial>, say) and still returns a model with
// the element reset to zero, so any logged error makes the file invalid.
class CapturedConsole : public console_bridge::OutputHandler {
 public:
  CapturedConsole() {
    previous_ = console_bridge::getOutputHandler();
    console_bridge::useOutputHandler(this);
  }
  ~CapturedConsole() override { console_bridge::useOutputHandler(previous_); }
  // Each message escaped and cut (it may quote the file's text), at most kShownMessages of them.
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (count_++ < kShownMessages) messages_.push_back(escaped_text(text, '\0', 4 * kShownBytes));
  }
  std::string messages() const {
    std::string text;
    for (const std::string& message : messages_) text += (text.empty() ? "" : "; ") + message;
    if (count_ > kShownMessages) text += "; and " + std::to_string(count_ - kShownMessages) + " more";
    return text;
  }

 private:
  static constexpr std::size_t kShownMessages = 3;
  console_bridge::OutputHandler* previous_ = nullptr;
  std::vector<std::string> messages_;
  std::size_t count_ = 0;
};

std::string vector_text(const Vec3& v) { return "(" + shortest(v.x()) + ", " + shortest(v.y()) + ", " + shortest(v.z()) + ")"; }

std::string named(const std::string& kind, const std::string& name) { return kind + " " + quote_name(name); }

void require_finite(const std::string& file, const std::string& element, std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) throw InputError(file, element, "number is not finite (NaN or Inf)");
}

// A moving joint's position limits [lower, upper]: ±Inf for a continuous joint or one without a
// <limit>; limits that are not finite or that cross (lower > upper: no position satisfies them,
// yet random states draw from them and locked joints are clamped into them) are refused.
std::pair<double, double> position_limits(const urdf::Joint& joint, const std::string& file) {
  if (joint.type == urdf::Joint::CONTINUOUS || !joint.limits)
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  const std::string element = named("joint", joint.name) + " <limit>";
  const double lower = joint.limits->lower, upper = joint.limits->upper;
  require_finite(file, element, {lower, upper});
  if (lower > upper)
    throw InputError(file, element, "lower " + shortest(lower) + " is above upper " + shortest(upper));
  return {lower, upper};
}

// Pose of a child frame in its parent (URDF <origin>) as the motion transform parent -> child:
// X_T of (F2) in docs/derivation.md, under the quarter-turn rule unless the spec turns it off;
// each origin the rule changed is added to chain.changes (or counted, when only by rounding).
Transform transform_from_pose(const urdf::Pose& pose, const ChainSpec& spec, Chain& chain, const std::string& element) {
  const std::string origin = element + " <origin>";
  require_finite(spec.urdf, origin,
                 {pose.position.x, pose.position.y, pose.position.z, pose.rotation.x, pose.rotation.y,
                  pose.rotation.z, pose.rotation.w});
  const OriginRotation rotation = origin_rotation(pose.rotation, spec.snap_quarter_turns);
  if (rotation.snapped[0] || rotation.snapped[1] || rotation.snapped[2]) {
    if (rotation.deviation < kRoundingOfQuarterTurns) {
      ++chain.exact_quarter_turns;
    } else {
      std::string written, taken;
      for (int k = 0; k < 3; ++k) {
        const std::string angle = shortest(rotation.rpy[k] + 0.0);  // + 0.0: -0 reads as 0
        written += (k ? ", " : "rpy (") + angle;
        taken += (k ? ", " : "(") + (rotation.snapped[k] ? quarter_turns_text(rotation.quarter_turns[k]) : angle);
      }
      chain.changes.push_back({origin, written + ")", taken + ")", rotation.deviation, "rad"});
    }
  }
  Transform X;
  X.E = rotation.R.transpose();
  X.r = Vec3(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

// Validates a link's <inertial> (mass >= 0, principal moments >= 0 and satisfying the triangle
// inequalities, i.e. a physically consistent rigid body) and returns its spatial inertia about
// the link frame's origin, in link coordinates.
Inertia link_inertia(const urdf::Link& link, const ChainSpec& spec, Chain& chain, double& mass) {
  const std::string& file = spec.urdf;
  mass = 0;
  if (!link.inertial) return Inertia{};
  const urdf::Inertial& in = *link.inertial;
  const std::string element = named("link", link.name) + " <inertial>";
  require_finite(file, element, {in.mass, in.ixx, in.ixy, in.ixz, in.iyy, in.iyz, in.izz});
  if (in.mass < 0) throw InputError(file, element, "negative mass " + std::to_string(in.mass));
  for (const auto& [name, value] : {std::pair<const char*, double>{"mass", in.mass}, {"ixx", in.ixx}, {"iyy", in.iyy}, {"izz", in.izz}})
    if (const std::string problem = magnitude_problem(value); !problem.empty())
      throw InputError(file, element, std::string(name) + " " + problem);
  Mat3 inertia_com;
  inertia_com << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Mat3>(inertia_com).eigenvalues();
  const double tolerance = 1e-12 * moments.cwiseAbs().sum();
  std::ostringstream principal;
  principal.precision(17);
  principal << "principal moments " << moments(0) << ", " << moments(1) << ", " << moments(2);
  if (moments(0) < -tolerance)
    throw InputError(file, element, "inertia tensor is not positive semi-definite (" + principal.str() + ")");
  if (moments(0) + moments(1) < moments(2) - tolerance)
    throw InputError(file, element,
                     "inertia tensor violates the triangle inequality I1 + I2 >= I3 (" + principal.str() +
                         "), no rigid body has it");
  const Transform link_to_com = transform_from_pose(in.origin, spec, chain, named("link", link.name) + " <inertial>");
  // Rotate the tensor from the inertial frame into link axes, then about the link origin (F3).
  const Mat3 R = link_to_com.E.transpose();
  const Mat3 rotated = R * inertia_com * R.transpose();
  const Vec3 com = link_to_com.r;
  const Mat3 cx = spatial::skew(com);
  mass = in.mass;
  // R I R^T and c× c× are symmetric in exact arithmetic, not always in floating point; the
  // sweeps rely on symmetric blocks (they compute one triangle), so make it exact.
  Mat3 about_origin = rotated - in.mass * cx * cx;
  const double asymmetry = (about_origin - about_origin.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 0)
    chain.changes.push_back({element, "the tensor about the link origin (R I R^T - m c x c x, rounded: not symmetric)",
                             "its upper triangle mirrored", asymmetry, "kg m^2"});
  spatial::symmetrize_from_upper(about_origin);
  return Inertia::rigid(in.mass, in.mass * com, about_origin);
}

std::vector<std::string> link_names(const urdf::ModelInterface& model) {
  std::vector<std::string> names;
  for (const auto& [name, link] : model.links_) names.push_back(name);
  return names;
}

urdf::LinkConstSharedPtr find_link(const urdf::ModelInterface& model, const std::string& name,
                                   const std::string& file, const std::string& role) {
  auto link = model.getLink(name);
  if (!link)
    throw InputError(file, role + " link " + quote_name(name),
                     "no such link in the URDF" + nearest_name_hint(name, link_names(model)));
  return link;
}

// Whether a moving joint lies below `top` (a walk with a stack of links, not recursion: a chain of
// fixed joints may be as long as the file allows); `budget` counts the joints visited, so that a
// cycle (urdfdom accepts a link that is the child of two joints) ends the search as an error.
bool moves_below(const urdf::Link& top, std::size_t& budget, const std::string& file) {
  std::vector<const urdf::Link*> stack{&top};
  while (!stack.empty()) {
    const urdf::Link& link = *stack.back();
    stack.pop_back();
    for (const auto& joint : link.child_joints) {
      if (budget-- == 0)
        throw InputError(file, named("link", link.name), "the joints form a cycle through this link; a URDF must be a tree");
      if (joint->type != urdf::Joint::FIXED) return true;
    }
    for (const auto& child : link.child_links) stack.push_back(child.get());
  }
  return false;
}

// The deepest link below `root` along the one branch that moves: at a link with several
// children, the branch is the only child with a moving joint below it (side branches of fixed
// links, a sensor or a tool flange, are lumped and do not end the chain); where several children
// all hang on fixed joints (a flange carrying a tool frame and a sensor frame), the link itself is
// the tip: the body after the last moving joint, which carries them all. Two moving branches are
// ambiguous. More steps down than there are links means a cycle.
std::string deepest_link(const urdf::Link& root, std::size_t link_count, const std::string& file,
                         const std::string& naming_the_tip) {
  const urdf::Link* link = &root;
  for (std::size_t steps = 0; !link->child_links.empty(); ++steps) {
    if (steps == link_count)
      throw InputError(file, named("link", link->name),
                       "the joints form a cycle through this link; a URDF must be a tree");
    std::vector<const urdf::Link*> moving;
    for (std::size_t c = 0; c < link->child_links.size(); ++c) {
      std::size_t budget = link_count;
      const auto& joint = link->child_joints.at(c);
      if (joint->type != urdf::Joint::FIXED || moves_below(*link->child_links[c], budget, file))
        moving.push_back(link->child_links[c].get());
    }
    if (link->child_links.size() > 1 && moving.empty()) break;
    if (link->child_links.size() > 1 && moving.size() != 1) {
      std::vector<std::string> names;
      for (const auto& child : link->child_links) names.push_back(quote_name(child->name));
      const std::string children = listed(names);
      throw InputError(file, named("link", link->name),
                       "the tree branches here (children " + children + ", " + std::to_string(moving.size()) +
                           " of them with moving joints below), so there is no default tip; name the tip link: " +
                           naming_the_tip);
    }
    link = moving.empty() ? link->child_links.front().get() : moving.front();
  }
  return link->name;
}

// The links above `link`, its parent first, at most `limit` of them (a cycle of links has no top).
std::vector<std::string> links_above(const urdf::ModelInterface& model, const std::string& link, std::size_t limit) {
  std::vector<std::string> above;
  for (auto l = model.getLink(link); l && l->parent_joint && above.size() < limit;) {
    above.push_back(l->parent_joint->parent_link_name);
    l = model.getLink(above.back());
  }
  return above;
}

// Why `root` does not reach `tip`, with a root that does: the lowest link above both (the nearest
// to the root that was meant), or a swap where the tip is above the root.
std::string unreachable_tip(const urdf::ModelInterface& model, const std::string& root, const std::string& tip) {
  const std::string reason = "not connected: " + quote_name(tip) + " is not below " + quote_name(root) + " in the URDF tree";
  const std::vector<std::string> above_root = links_above(model, root, model.links_.size());
  if (std::find(above_root.begin(), above_root.end(), tip) != above_root.end())
    return reason + "; it is above it: swap root and tip";
  const std::string top = model.getRoot()->name;
  for (const std::string& link : links_above(model, tip, model.links_.size()))
    if (std::find(above_root.begin(), above_root.end(), link) != above_root.end())
      return reason + "; root " + quote_name(link) + ", above both, reaches it" +
             (link == top ? "" : ", as does the URDF's root " + quote_name(top));
  return reason;
}

// Joints from root to tip, root first.
std::vector<urdf::JointConstSharedPtr> path_joints(const urdf::ModelInterface& model, const std::string& root,
                                                   const std::string& tip, const std::string& file) {
  std::vector<urdf::JointConstSharedPtr> joints;
  for (auto link = model.getLink(tip); link->name != root;) {
    if (!link->parent_joint)
      throw InputError(file, "links " + quote_name(root) + " and " + quote_name(tip), unreachable_tip(model, root, tip));
    // urdfdom accepts a cycle of links that each have a parent (apart from the root's tree):
    // walking up from a link on it never ends.
    if (joints.size() == model.links_.size())
      throw InputError(file, "links " + quote_name(root) + " and " + quote_name(tip),
                       "not connected: the joints above " + quote_name(tip) + " form a cycle; a URDF must be a tree");
    joints.push_back(link->parent_joint);
    link = model.getLink(link->parent_joint->parent_link_name);
  }
  return {joints.rbegin(), joints.rend()};
}

// The unit axis of a moving joint, validated.
// One whose length is not 1 is scaled to it and added to chain.changes.
Vec3 unit_axis(const urdf::Joint& joint, const ChainSpec& spec, Chain& chain) {
  const std::string& file = spec.urdf;
  const std::string element = named("joint", joint.name) + " <axis>";
  const auto& a = joint.axis;
  require_finite(file, element, {a.x, a.y, a.z});
  // The norm of an axis with a huge component (1e201) overflows to Inf, and axis / Inf is no unit
  // vector (a fuzz_urdf finding): such an axis is scaled by its largest component first.
  Vec3 axis(a.x, a.y, a.z);
  if (!std::isfinite(axis.norm())) axis /= axis.cwiseAbs().maxCoeff();
  if (!(axis.norm() > 1e-12)) throw InputError(file, element, "axis has zero length");
  const Vec3 unit = axis / axis.norm();
  const Vec3 written(a.x, a.y, a.z);
  // The change as 1 - 1/|a|: finite where |a| overflows (it is then 1).
  if (unit != written)
    chain.changes.push_back({element, vector_text(written), "the unit vector " + vector_text(unit),
                             std::abs(1 - 1 / written.norm()), "(1 - 1/|axis|)"});
  return unit;
}

bool is_moving(const urdf::Joint& joint) {
  return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
         joint.type == urdf::Joint::PRISMATIC;
}

std::string lock_location(const ChainSpec& spec, const std::string& joint) {
  const auto at = spec.locked_joint_locations.find(joint);
  return at == spec.locked_joint_locations.end() ? "command line" : at->second;
}

// Holds a moving joint at one position so that the links behind it are rigid (F4): the spec's
// locked_joints entry (within the joint's limits), else 0 clamped into its limits. Adds it to
// chain.locked_joints (carried by `body`) and returns its motion X_J(q_lock) (F2): the child
// frame in the joint frame.
Transform lock_joint(const urdf::Joint& joint, std::size_t body, const ChainSpec& spec, Chain& chain) {
  const auto [lower, upper] = position_limits(joint, spec.urdf);
  LockedJoint locked{joint.name, body, std::clamp(0.0, lower, upper), false};
  if (const auto given = spec.locked_joints.find(joint.name); given != spec.locked_joints.end()) {
    const std::string element = element_path("locked_joints", joint.name);
    if (!std::isfinite(given->second)) throw InputError(lock_location(spec, joint.name), element, "position is not finite");
    if (given->second < lower || given->second > upper)
      throw InputError(lock_location(spec, joint.name), element,
                       "position " + shortest(given->second) + " is outside the joint's limits [" + shortest(lower) +
                           ", " + shortest(upper) + "] in " + spec.urdf);
    locked.position = given->second;
    locked.from_scene = true;
  }
  chain.locked_joints.push_back(locked);
  const Vec3 axis = unit_axis(joint, spec, chain);
  Transform motion;
  if (joint.type == urdf::Joint::PRISMATIC) motion.r = axis * locked.position;
  else motion.E = Eigen::AngleAxisd(locked.position, axis).toRotationMatrix().transpose();
  return motion;
}

// A <mimic> on a joint the model moves or locks: its source must be a joint of the URDF and its
// numbers finite; it is added to chain.mimics, to be said (model_notes).
void note_mimic(const urdf::ModelInterface& model, const urdf::Joint& joint, const ChainSpec& spec, Chain& chain) {
  if (!joint.mimic) return;
  const urdf::JointMimic& mimic = *joint.mimic;
  const std::string element = named("joint", joint.name) + " <mimic>";
  require_finite(spec.urdf, element, {mimic.multiplier, mimic.offset});
  if (!model.getJoint(mimic.joint_name)) {
    std::vector<std::string> joints;
    for (const auto& [name, other] : model.joints_) joints.push_back(name);
    throw InputError(spec.urdf, element,
                     "follows joint " + quote_name(mimic.joint_name) + ", which the URDF does not have" +
                         nearest_name_hint(mimic.joint_name, joints));
  }
  chain.mimics.push_back({joint.name, mimic.joint_name, mimic.multiplier, mimic.offset});
}

// A joint whose <mimic> follows itself, or a cycle of <mimic>s (a follows b, b follows a): none
// of them has a position of its own that the others follow. Each joint is walked once.
void refuse_mimic_cycles(const urdf::ModelInterface& model, const std::string& urdf) {
  enum class Walk { on_the_path, done };
  std::map<std::string, Walk> walked;
  for (const auto& [start, first] : model.joints_) {
    std::vector<std::string> path;  // joints of this walk, each following the one before
    urdf::JointConstSharedPtr joint = first;
    while (joint && !walked.count(joint->name)) {
      walked[joint->name] = Walk::on_the_path;
      path.push_back(joint->name);
      const urdf::JointConstSharedPtr next = joint->mimic ? model.getJoint(joint->mimic->joint_name) : nullptr;
      joint = next;
      if (!next || walked.count(next->name) == 0 || walked.at(next->name) == Walk::done) continue;
      if (next->name == path.back())
        throw InputError(urdf, named("joint", next->name) + " <mimic>", "follows the joint itself");
      std::string cycle;
      for (auto it = std::find(path.begin(), path.end(), next->name); it != path.end(); ++it) cycle += quote_name(*it) + " -> ";
      throw InputError(urdf, named("joint", next->name) + " <mimic>",
                       "the <mimic>s of joints " + cycle + quote_name(next->name) +
                           " form a cycle: none of them has a position of its own to follow");
    }
    for (const std::string& name : path) walked[name] = Walk::done;
  }
}

// The branches that leave the chain (chain.hpp), lumped into the body that carries them (F4):
// behind moving joints held at their locked position, so that every link a moving body carries
// counts.
class OffChainLumper {
 public:
  OffChainLumper(const urdf::ModelInterface& model, const ChainSpec& spec, Chain& chain)
      : model_(model), spec_(spec), chain_(chain) {}

  // Lumps the branches that leave the chain at each of `chain_links` (root to tip) into the body
  // carrying that link, then lists what no moving body carries.
  void run(const std::vector<std::string>& chain_links) {
    const std::set<std::string> on_chain(chain_links.begin(), chain_links.end());
    for (const std::string& name : chain_links) {
      const Frame frame = chain_.frames.at(name);
      if (frame.body == 0) continue;  // carried by the fixed base: moves nothing (left_out)
      for (const auto& joint : model_.getLink(name)->child_joints)
        if (on_chain.count(joint->child_link_name) == 0) carry(*joint, frame.body, frame.X, "");
    }
    check_unused_locks();
    list_left_out();
  }

 private:
  // Lumps `top`'s child link and everything below it into `body`; `body_to_parent` is the
  // transform from the body's frame to the joint's parent link frame. Depth first, each joint
  // before the joints below it, with a stack of joints, not recursion: a branch may be as long
  // as the file allows.
  void carry(const urdf::Joint& top, std::size_t body, const Transform& body_to_parent, const std::string& locked_by) {
    struct Step {
      const urdf::Joint* joint;
      Transform body_to_parent;
      std::string locked_by;
    };
    std::vector<Step> stack{{&top, body_to_parent, locked_by}};
    while (!stack.empty()) {
      Step step = std::move(stack.back());
      stack.pop_back();
      const urdf::Joint& joint = *step.joint;
      const std::string& file = spec_.urdf;
      const std::string element = named("joint", joint.name);
      const auto child = model_.getLink(joint.child_link_name);
      if (chain_.frames.count(child->name) != 0)
        throw InputError(file, named("link", child->name), "the joints form a cycle through this link; a URDF must be a tree");
      Transform parent_to_child = transform_from_pose(joint.parent_to_joint_origin_transform, spec_, chain_, element);
      if (is_moving(joint)) {
        note_mimic(model_, joint, spec_, chain_);
        parent_to_child = lock_joint(joint, body, spec_, chain_) * parent_to_child;
        step.locked_by = joint.name;
      } else if (joint.type != urdf::Joint::FIXED) {
        throw InputError(file, element,
                         "a floating or planar joint off the chain (below " + quote_name(chain_.bodies[body].link) +
                             ") cannot be locked at one position; make it fixed, or choose a chain that avoids it");
      }
      const Transform body_to_child = parent_to_child * step.body_to_parent;
      double mass = 0;
      const Inertia inertia = link_inertia(*child, spec_, chain_, mass);
      Body& b = chain_.bodies[body];
      b.inertia = b.inertia + inertia.transformed_to_parent(body_to_child);
      b.mass += mass;
      b.lumped_links.push_back({child->name, mass, step.locked_by});
      chain_.frames[child->name] = Frame{body, body_to_child};
      for (auto grandchild = child->child_joints.rbegin(); grandchild != child->child_joints.rend(); ++grandchild)
        stack.push_back({grandchild->get(), body_to_child, step.locked_by});
    }
  }

  // A locked position for a joint that was not locked is a mistake: say why.
  void check_unused_locks() const {
    std::vector<std::string> lockable;
    for (const auto& locked : chain_.locked_joints) lockable.push_back(locked.name);
    for (const auto& [name, position] : spec_.locked_joints) {
      if (std::find(lockable.begin(), lockable.end(), name) != lockable.end()) continue;
      const std::string element = element_path("locked_joints", name);
      const auto joint = model_.getJoint(name);
      std::string reason;
      if (!joint) reason = "no joint of that name in " + spec_.urdf + nearest_name_hint(name, lockable);
      else if (chain_.joint_index(name) != 0)
        reason = "is a moving joint of the chain; only joints off the chain, and <mimic> joints, are locked";
      else if (!is_moving(*joint)) reason = "is not a revolute, continuous or prismatic joint; there is nothing to lock";
      else reason = "is not carried by a moving body of the chain (it hangs off the fixed base or lies outside the chain's tree); locking it changes nothing";
      throw InputError(lock_location(spec_, name), element, "joint " + quote_name(name) + " " + reason);
    }
  }

  void list_left_out() {
    for (const auto& [name, link] : model_.links_) {
      if (chain_.frames.count(name) != 0) continue;
      // Up the tree to the first link the chain knows (only the base's links can be met: every
      // moving body's branches are lumped); the link count bounds the walk against cycles.
      std::string reason = "not below the root link " + quote_name(chain_.root_link);
      urdf::LinkConstSharedPtr above = link;
      for (std::size_t steps = 0; above->parent_joint && steps < model_.links_.size(); ++steps) {
        above = model_.getLink(above->parent_joint->parent_link_name);
        if (chain_.frames.count(above->name) != 0) {
          reason = "carried by the fixed base (below " + quote_name(above->name) + "): it moves nothing";
          break;
        }
      }
      chain_.left_out.push_back({name, link->inertial ? link->inertial->mass : 0.0, reason});
    }
  }

  const urdf::ModelInterface& model_;
  const ChainSpec& spec_;
  Chain& chain_;
};

// Each number of the URDF is finite, but products and sums of them need not be: a centre of mass
// at 1e304 m makes m c× c× overflow (a fuzz_urdf finding), origins of 1e308 add up to Inf.
void check_finite_model(const Chain& chain) {
  const auto finite = [](const Transform& X) { return X.E.allFinite() && X.r.allFinite(); };
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const Inertia& M = chain.bodies[i].inertia;
    if (!(M.A.allFinite() && M.B.allFinite() && M.C.allFinite() && std::isfinite(chain.bodies[i].mass)))
      throw InputError(chain.source, named("link", chain.bodies[i].link) + " <inertial>",
                       "the spatial inertia about the link's origin, with the links lumped into it, is not finite: "
                       "a mass, centre of mass or origin is too large");
    if (!finite(chain.joints[i].tree_transform))
      throw InputError(chain.source, named("joint", chain.joints[i].name) + " <origin>",
                       "the transform from the previous moving body is not finite: origins too large");
  }
  for (const auto& [link, frame] : chain.frames)
    if (!finite(frame.X))
      throw InputError(chain.source, named("link", link), "its frame is not finite: origins too large");
}

// Every body without a body beyond it (the chain's last, each branch's last) must be able to
// accelerate about its own joint: nothing else contributes to its D_i.
void check_outermost_joints_can_accelerate(const Chain& chain) {
  std::vector<bool> has_child(chain.dof() + 1, false);
  for (std::size_t i = 1; i <= chain.dof(); ++i) has_child[chain.parent[i]] = true;
  for (std::size_t n = 1; n <= chain.dof(); ++n) {
    if (has_child[n]) continue;
    const Joint& joint = chain.joints[n];
    const Inertia& inertia = chain.bodies[n].inertia;
    spatial::Motion<double> S;
    (joint.type == JointType::revolute ? S.angular : S.linear) = joint.axis;
    const double D = joint.rotor_inertia + spatial::dot(inertia * S, S);
    // Relative to the body's own inertia of the joint's kind (rotational about its origin for a
    // revolute joint, translational for a prismatic one), as the solver's joint-inertia policy
    // judges D_i (docs/stability.md, "Joint-space inertia D_i"): the same decision in any units.
    // A thin rod spun about its own axis (D / trace ~ (r / l)^2) is valid; a massless body, a
    // point mass or a rod of zero radius on the axis is not.
    const double scale =
        joint.rotor_inertia + (joint.type == JointType::revolute ? inertia.A.trace() : inertia.C.trace());
    if (!(D > 1000 * std::numeric_limits<double>::epsilon() * scale))
      throw InputError(chain.source, named("joint", joint.name),
                       "the last moving body (" + quote_name(chain.bodies[n].link) +
                           " with everything fixed to it) has no inertia about this joint's axis and the joint has "
                           "no rotor inertia, so D_N = 0 and its acceleration is undefined; give the link an "
                           "<inertial> or the joint a rotor inertia");
  }
}

void apply_rotor_inertia(Chain& chain, const std::map<std::string, double>& rotor_inertia, const std::string& source) {
  std::vector<std::string> names;
  for (std::size_t i = 1; i <= chain.dof(); ++i) names.push_back(chain.joints[i].name);
  for (const auto& [name, value] : rotor_inertia) {
    const std::string element = "rotor inertia of joint " + quote_name(name);
    const std::size_t i = chain.joint_index(name);
    if (i == 0)
      throw InputError(source, element, "no moving joint of that name on " + chain.extent() + nearest_name_hint(name, names));
    if (!std::isfinite(value) || value < 0) throw InputError(source, element, "must be a finite number >= 0");
    chain.joints[i].rotor_inertia = value;
  }
}

}  // namespace

std::shared_ptr<const std::string> read_urdf(const std::string& path) {
  return std::make_shared<const std::string>(read_input_file(path, kMaxUrdfBytes, "URDF"));
}

Chain load_chain(const ChainSpec& spec) {
  const std::string& urdf_path = spec.urdf;
  const std::string& root_link = spec.root_link;
  const std::string& tip_link = spec.tip_link;
  const std::shared_ptr<const std::string> bytes = spec.urdf_bytes ? spec.urdf_bytes : read_urdf(urdf_path);
  const std::string& text = *bytes;
  // Before the parser: its recursion follows the nesting, its memory the elements.
  const XmlOutline outline = xml_outline(text);
  if (outline.depth > kMaxXmlDepth)
    throw InputError(urdf_path + ":" + std::to_string(outline.deepest_line), "<robot>",
                     "elements nested " + std::to_string(outline.depth) + " deep, more than the limit of " +
                         std::to_string(kMaxXmlDepth) + " (README, \"Limits\"; a URDF needs 4)");
  for (const auto& [count, kind, limit] : {std::tuple{outline.links, "<link>", kMaxLinks}, {outline.joints, "<joint>", kMaxJoints}})
    if (count > limit)
      throw InputError(urdf_path, "<robot>",
                       std::to_string(count) + " " + kind + " elements, more than the limit of " + std::to_string(limit) +
                           " (README, \"Limits\")");
  if (outline.declaration_line != 0)
    throw InputError(urdf_path + ":" + std::to_string(outline.declaration_line) + ":" +
                         std::to_string(outline.declaration_column),
                     "XML",
                     "a document type declaration (<!DOCTYPE ...>): a URDF has no DTD, and TinyXML, the XML reader "
                     "under urdfdom, reads none (it then finds no 'robot' element); remove it");
  if (outline.elements > kMaxXmlElements)
    throw InputError(urdf_path + ":" + std::to_string(outline.element_past_limit_line),
                     "<" + inert_text(outline.element_past_limit) + ">",
                     "more than " + std::to_string(kMaxXmlElements) +
                         " XML elements, the limit (README, \"Limits\"; a link or joint takes a few to a few dozen); not read further");

  urdf::ModelInterfaceSharedPtr model;
  // urdfdom's links own their children: a long chain would be freed by one destructor calling the
  // next, as deep as the chain. Cut those links first, whatever leaves this function.
  struct Teardown {
    urdf::ModelInterfaceSharedPtr& model;
    ~Teardown() {
      if (!model) return;
      for (auto& [name, link] : model->links_) {
        link->child_links.clear();
        link->child_joints.clear();
      }
    }
  } teardown{model};
  std::string padded_text;
  {
    CapturedConsole console;
    // TinyXML (under urdfdom) steps over a UTF-8 lead byte's continuation bytes without looking
    // for the end of the text, so a lead byte among the last bytes makes it read past the
    // string's terminator (an AddressSanitizer heap-buffer-overflow found by fuzz_urdf, input kept
    // as fuzz/regressions/urdf/reject_utf8_lead_byte_at_end.urdf). NUL bytes after the text keep
    // such a read inside the buffer; the parser stops at the first NUL either way.
    padded_text = text + std::string(8, '\0');
    check_xml_syntax(padded_text, urdf_path, outline);  // the outline read above: the padding adds no element
    model = urdf::parseURDF(padded_text);
    if (!model || !console.messages().empty())
      throw InputError(urdf_path, "<robot>",
                       "not a valid URDF: " + (console.messages().empty() ? "urdfdom rejected it" : console.messages()));
  }
  refuse_mimic_cycles(*model, urdf_path);

  Chain chain;
  chain.source = urdf_path;
  chain.root_link = root_link.empty() ? model->getRoot()->name : root_link;
  const auto root = find_link(*model, chain.root_link, urdf_path, "root");
  chain.tip_link = tip_link.empty() ? deepest_link(*root, model->links_.size(), urdf_path, spec.naming_the_tip) : tip_link;
  find_link(*model, chain.tip_link, urdf_path, "tip");

  // The base. A fixed one's inertia moves nothing; its mass (the root link's and the links fixed
  // to it on the way to the first moving joint, lumped below) is kept for the listing
  // (lumping_summary). A floating base's root link is body 6 (add_floating_base).
  const double base_mass = !spec.floating_base && root->inertial ? root->inertial->mass : 0.0;
  chain.bodies.push_back(Body{chain.root_link, {}, Inertia{}, base_mass});
  chain.joints.push_back(Joint{});
  chain.parent.push_back(0);
  if (spec.floating_base) {
    for (const std::string& name : floating_base_joint_names())
      if (model->getJoint(name))
        throw InputError(urdf_path, named("joint", name),
                         "the name is taken by the floating base's coordinates; rename the joint for a floating base");
    double mass = 0;
    const Inertia inertia = link_inertia(*root, spec, chain, mass);
    add_floating_base(chain, inertia, mass);
  }
  chain.frames[chain.root_link] = Frame{chain.dof(), Transform::identity()};
  std::vector<std::string> chain_links{chain.root_link};  // every link on a root-to-tip path

  // The tips: the paths from the root to each, in order; a joint met again on a later path
  // (the trunk the branches share) is already placed.
  chain.branch_tips = spec.branch_tips;
  std::vector<std::string> tips{chain.tip_link};
  for (const std::string& tip : chain.branch_tips) {
    find_link(*model, tip, urdf_path, "tip");
    if (std::find(tips.begin(), tips.end(), tip) != tips.end())
      throw InputError(urdf_path, "tip link " + quote_name(tip), "named twice among the tips");
    tips.push_back(tip);
  }
  for (const std::string& tip : tips)
    for (const auto& urdf_joint : path_joints(*model, chain.root_link, tip, urdf_path)) {
      const auto child = model->getLink(urdf_joint->child_link_name);
      if (chain.frames.count(child->name) != 0) continue;  // on an earlier tip's path
      const std::string element = named("joint", urdf_joint->name);
      const Transform origin = transform_from_pose(urdf_joint->parent_to_joint_origin_transform, spec, chain, element);
      double mass = 0;
      const Inertia child_inertia = link_inertia(*child, spec, chain, mass);
      chain_links.push_back(child->name);
      // The parent link's frame: on its body, at the transform from that body's frame.
      const Frame above = chain.frames.at(urdf_joint->parent_link_name);
      // A <mimic> joint is a joint of its own (MimicJoint): it moves, unless the scene locks it.
      if (is_moving(*urdf_joint)) note_mimic(*model, *urdf_joint, spec, chain);
      const bool locked_mimic = urdf_joint->mimic && is_moving(*urdf_joint) && spec.locked_joints.count(urdf_joint->name);

      // A fixed joint, or a locked one: its child is lumped into the body above (F4).
      if (urdf_joint->type == urdf::Joint::FIXED || locked_mimic) {
        const Transform motion = locked_mimic ? lock_joint(*urdf_joint, above.body, spec, chain) : Transform::identity();
        const Transform body_to_link = motion * origin * above.X;
        chain.frames[child->name] = Frame{above.body, body_to_link};
        Body& b = chain.bodies[above.body];
        if (above.body > 0) b.inertia = b.inertia + child_inertia.transformed_to_parent(body_to_link);
        b.mass += mass;
        b.lumped_links.push_back({child->name, mass, locked_mimic ? urdf_joint->name : ""});
        continue;
      }
      switch (urdf_joint->type) {
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS:
        case urdf::Joint::PRISMATIC: {
          Joint joint;
          joint.name = urdf_joint->name;
          joint.type = urdf_joint->type == urdf::Joint::PRISMATIC ? JointType::prismatic : JointType::revolute;
          joint.continuous = urdf_joint->type == urdf::Joint::CONTINUOUS;
          joint.axis = unit_axis(*urdf_joint, spec, chain);
          joint.tree_transform = origin * above.X;
          if (const auto& limits = urdf_joint->limits) {
            require_finite(urdf_path, element + " <limit>", {limits->effort, limits->velocity});
            if (limits->effort < 0 || limits->velocity < 0)
              throw InputError(urdf_path, element + " <limit>", "effort and velocity limits must not be negative");
            // URDF writes 0 where no limit is known; it means "unlimited" here.
            if (limits->effort > 0) joint.effort_limit = limits->effort;
            if (limits->velocity > 0) joint.velocity_limit = limits->velocity;
          }
          std::tie(joint.lower, joint.upper) = position_limits(*urdf_joint, urdf_path);
          if (const auto& dynamics = urdf_joint->dynamics; dynamics && (dynamics->damping != 0 || dynamics->friction != 0))
            chain.unmodelled_dynamics.push_back({joint.name, dynamics->damping, dynamics->friction});
          chain.joints.push_back(joint);
          chain.bodies.push_back(Body{child->name, {}, child_inertia, mass});
          chain.parent.push_back(above.body);
          chain.frames[child->name] = Frame{chain.bodies.size() - 1, Transform::identity()};
          break;
        }
        case urdf::Joint::FLOATING:
          throw InputError(urdf_path, element,
                           "a floating joint inside the chain is not supported; for a free-floating robot take its "
                           "child " + quote_name(child->name) +
                               " as the root and let the base float (scene: base: floating; sweepgen solve: "
                               "--floating-base)");
        case urdf::Joint::PLANAR:
          throw InputError(urdf_path, element,
                           "planar joints are not supported (trees of revolute, continuous, prismatic and fixed joints "
                           "only)");
        default:
          throw InputError(urdf_path, element, "joint type unknown");
      }
    }
  if (chain.dof() == 0) throw InputError(urdf_path, chain.extent(), "no moving joint on it");
  OffChainLumper(*model, spec, chain).run(chain_links);
  check_finite_model(chain);
  apply_rotor_inertia(chain, spec.rotor_inertia, spec.rotor_inertia_source);
  check_outermost_joints_can_accelerate(chain);
  if (spec.couple_mimics) chain.couplings = mimic_couplings(*model, chain, urdf_path, spec.mimic_location);
  // The quarter-turn rule's listing shows the angles as written (urdfdom keeps a quaternion), and
  // the rotation taken in the same form where it can (quarter_turns_as_written).
  if (std::any_of(chain.changes.begin(), chain.changes.end(), [](const ModelChange& c) { return c.unit == "rad"; })) {
    const auto written = written_rpy(padded_text);
    for (ModelChange& change : chain.changes)
      if (const auto text = written.find(change.element); change.unit == "rad" && text != written.end()) {
        change.written = "rpy " + quote_name(text->second);
        if (const std::string taken = quarter_turns_as_written(change.taken_as, text->second); !taken.empty())
          change.taken_as = taken;
      }
  }
  return chain;
}

}  // namespace sweepgen::model
