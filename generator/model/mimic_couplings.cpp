#include "model/mimic_couplings.hpp"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>

#include "model/error.hpp"
#include "model/inert_text.hpp"

namespace sweepgen::model {

namespace {

// Why the model does not move joint `name`, for the message.
std::string not_moved_reason(const urdf::ModelInterface& model, const Chain& chain, const std::string& name) {
  if (model.getJoint(name)->type == urdf::Joint::FIXED) return "a fixed joint";
  const auto held = std::find_if(chain.locked_joints.begin(), chain.locked_joints.end(),
                                 [&name](const LockedJoint& j) { return j.name == name; });
  if (held != chain.locked_joints.end())
    return "locked at " + shortest(held->position) + (held->from_scene ? " (locked_joints)" : " (off the chain)");
  return "not on a path from the root to a tip";
}

}  // namespace

std::vector<JointCoupling> mimic_couplings(const urdf::ModelInterface& model, const Chain& chain, const std::string& urdf,
                                           const std::string& mode_location) {
  std::vector<JointCoupling> couplings;
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    if (chain.joints[i].floating_base_coordinate) continue;
    urdf::JointConstSharedPtr joint = model.getJoint(chain.joints[i].name);
    if (!joint || !joint->mimic) continue;
    const std::string element = "joint " + quote_name(joint->name) + " <mimic>";
    // (M1) composed: q = k q_cur + o and q_cur = k' q_next + o' give q = k k' q_next + (k o' + o).
    JointCoupling coupling{i, 0, 1, 0, {}};
    while (joint->mimic) {
      const urdf::JointMimic& mimic = *joint->mimic;
      const urdf::JointConstSharedPtr next = model.getJoint(mimic.joint_name);
      if (!next)
        throw InputError(urdf, "joint " + quote_name(joint->name) + " <mimic>",
                         "follows joint " + quote_name(mimic.joint_name) + ", which the URDF does not have");
      coupling.offset += coupling.multiplier * mimic.offset;
      coupling.multiplier *= mimic.multiplier;
      if (next->mimic) coupling.through.push_back(next->name);
      joint = next;
    }
    std::string through;
    for (const std::string& name : coupling.through) through += (through.empty() ? " (through " : ", ") + quote_name(name);
    if (!through.empty()) through += ")";
    coupling.source = chain.joint_index(joint->name);
    if (coupling.source == 0 || chain.joints[coupling.source].floating_base_coordinate)
      throw InputError(urdf, element,
                       "coupled (mimic: coupled, " + mode_location + "), it follows joint " + quote_name(joint->name) +
                           through + ", which the model does not move: " + not_moved_reason(model, chain, joint->name) +
                           "; add a tip beyond " + quote_name(joint->name) + " (tips), or lock " +
                           quote_name(chain.joints[i].name) + " (locked_joints)");
    if (coupling.multiplier == 0)
      throw InputError(urdf, element,
                       "coupled (mimic: coupled, " + mode_location + "), its multiplier to joint " +
                           quote_name(joint->name) + through + " is 0: the joint does not move; lock it (locked_joints)");
    couplings.push_back(coupling);
  }
  return couplings;
}

}  // namespace sweepgen::model
