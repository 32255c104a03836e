#include "model/model_notes.hpp"

#include <algorithm>
#include <sstream>

#include "model/error.hpp"
#include "model/quarter_turns.hpp"

namespace sweepgen::model {

namespace {

// One note and its kind, the line that model_note_summary gives the kind where it has several.
struct Note {
  const char* kind;
  std::string text;
};

constexpr const char* kMimic = "<mimic> joints, each taken as a joint of its own or locked";
constexpr const char* kCoupled = "<mimic> joints held to their sources exactly (mimic: coupled)";
constexpr const char* kLocked = "joints off the chain locked at a default position (scene key locked_joints)";
constexpr const char* kDynamics = "joints whose <dynamics> is not modelled (add its torques to tau_ff)";
constexpr const char* kChanged = "numbers taken otherwise than written";
constexpr const char* kRule = "rules of the loader";

std::vector<Note> notes_of(const Chain& chain) {
  std::vector<Note> lines;
  const auto line = [&lines](const char* kind, auto&&... parts) {
    std::ostringstream text;
    (text << ... << parts);
    lines.push_back({kind, text.str()});
  };
  const auto locked = [&chain](const std::string& name) {
    return std::find_if(chain.locked_joints.begin(), chain.locked_joints.end(),
                        [&name](const LockedJoint& j) { return j.name == name; });
  };
  for (const auto& mimic : chain.mimics) {
    std::ostringstream written;
    written << "joint " << quote_name(mimic.joint) << " is a <mimic> of " << quote_name(mimic.source) << " (q = "
            << mimic.multiplier << " q_source + " << mimic.offset << "): ";
    const std::size_t i = chain.joint_index(mimic.joint);
    if (const JointCoupling* coupling = i != 0 ? chain.coupling_of(i) : nullptr) {
      std::string through;
      for (const std::string& name : coupling->through) through += ", through " + quote_name(name);
      line(kCoupled, written.str(), "here joint ", i, " is coupled to joint ",
           quote_name(chain.joints[coupling->source].name), through, " (q = ", coupling->multiplier, " q_source + ",
           coupling->offset, "): q and qd hold no entry for it; coupling_torque[",
           coupling - chain.couplings.data(), "] is its transmission's torque");
    } else if (i != 0)
      line(kMimic, written.str(), "here it is a joint of its own, joint ", i,
           " of the chain; the application enforces the coupling (through tau_ff or a constraint) or locks the joint "
           "(locked_joints)");
    else if (const auto held = locked(mimic.joint); held != chain.locked_joints.end())
      line(kMimic, written.str(), "here it is locked at ", held->position, held->from_scene ? " (locked_joints)" : " (default)",
           "; the coupling is not modelled");
  }
  const auto is_mimic = [&chain](const std::string& name) {
    return std::any_of(chain.mimics.begin(), chain.mimics.end(), [&name](const MimicJoint& m) { return m.joint == name; });
  };
  for (const auto& held : chain.locked_joints)
    if (!held.from_scene && !is_mimic(held.name))  // a <mimic> joint's lock is said with its coupling above
      line(kLocked, "joint ", quote_name(held.name), " off the chain is locked at ", held.position,
           " (0 clamped into its limits; set locked_joints in the scene to choose), carrying its links on ",
           inert_text(chain.bodies[held.body].link));
  for (const auto& dynamics : chain.unmodelled_dynamics)
    line(kDynamics, "joint ", quote_name(dynamics.joint), ": the URDF's <dynamics> (damping ", dynamics.damping, ", friction ",
         dynamics.friction, ") is not modelled; add the torques it stands for to tau_ff (e.g. -damping * qd)");
  bool quarter_turns = chain.exact_quarter_turns > 0;
  // Inertias made symmetric change only rounding (the URDF's tensor is symmetric): one line for all.
  std::string symmetrised;
  double largest = 0;
  for (const auto& change : chain.changes) {
    if (change.unit == "kg m^2") {
      symmetrised += (symmetrised.empty() ? "" : ", ") + change.element.substr(0, change.element.rfind(" <inertial>"));
      largest = std::max(largest, change.deviation);
      continue;
    }
    line(kChanged, change.element, ": ", change.written, " taken as ", change.taken_as, " (changed by ", change.deviation, " ",
         change.unit, ")");
    quarter_turns = quarter_turns || change.unit == "rad";
  }
  if (!symmetrised.empty())
    line(kRule, "the inertia tensors about their link origins of ", symmetrised,
         " made exactly symmetric (the upper triangle mirrored; the rounding of R I R^T - m c x c x had made them differ "
         "by at most ", largest, " kg m^2)");
  if (chain.exact_quarter_turns > 0)
    line(kRule, chain.exact_quarter_turns, " <origin>s whose angles are multiples of pi/2 to the double's rounding (within ",
         kRoundingOfQuarterTurns, " rad) are taken as exact quarter turns");
  if (quarter_turns)
    line(kRule, "the quarter-turn rule (docs/derivation.md, F2) takes angles within 1e-10 rad of a multiple of pi/2 as exact; "
         "scene key snap_quarter_turns: false (or --no-snap-quarter-turns) takes the URDF literally");
  return lines;
}

}  // namespace

std::vector<std::string> model_notes(const Chain& chain) {
  std::vector<std::string> lines;
  for (const Note& note : notes_of(chain)) lines.push_back(note.text);
  return lines;
}

std::vector<std::string> model_note_summary(const Chain& chain) {
  const std::vector<Note> notes = notes_of(chain);
  std::vector<std::string> lines;
  for (const char* kind : {kMimic, kCoupled, kLocked, kDynamics, kChanged, kRule}) {
    std::vector<const Note*> of_kind;
    for (const Note& note : notes)
      if (note.kind == kind) of_kind.push_back(&note);
    if (of_kind.size() <= 2 || kind == kRule) {  // as many lines as a count and an example would take
      for (const Note* note : of_kind) lines.push_back(note->text);
      continue;
    }
    lines.push_back(std::to_string(of_kind.size()) + " " + kind + ", the first: " + of_kind.front()->text);
  }
  return lines;
}

}  // namespace sweepgen::model
