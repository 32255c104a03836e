#include "model/chain.hpp"

#include <sstream>

namespace sweepgen::model {

std::size_t Chain::joint_index(const std::string& name) const {
  for (std::size_t i = 1; i < joints.size(); ++i)
    if (joints[i].name == name) return i;
  return 0;
}

bool Chain::is_chain() const {
  for (std::size_t i = 1; i < parent.size(); ++i)
    if (parent[i] != i - 1) return false;
  return true;
}

bool Chain::supports(std::size_t ancestor, std::size_t body) const {
  while (body > ancestor) body = parent[body];
  return body == ancestor;
}

std::vector<std::string> lumping_summary(const Chain& chain) {
  std::vector<std::string> lines;
  const auto line = [&lines](auto&&... parts) {
    std::ostringstream text;
    (text << ... << parts);
    lines.push_back(text.str());
  };
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const Body& body = chain.bodies[i];
    double own = body.mass;
    for (const auto& lumped : body.lumped_links) own -= lumped.mass;
    std::ostringstream lumped_text;
    for (const auto& lumped : body.lumped_links)
      lumped_text << (lumped_text.tellp() > 0 ? ", " : "") << lumped.link << " " << lumped.mass << " kg"
                  << (lumped.locked_joint.empty() ? "" : " behind locked joint " + lumped.locked_joint);
    line("body ", i, " (joint ", chain.joints[i].name, "): ", body.mass, " kg = ", body.link, " ", own, " kg",
         body.lumped_links.empty() ? "" : " + lumped " + lumped_text.str());
  }
  for (const auto& locked : chain.locked_joints)
    line("locked joint ", locked.name, " at ", locked.position, (locked.from_scene ? " (scene)" : " (default)"),
         ", carried by ", chain.bodies[locked.body].link);
  for (const auto& link : chain.left_out) line("left out ", link.link, " ", link.mass, " kg: ", link.reason);
  return lines;
}

}  // namespace sweepgen::model
