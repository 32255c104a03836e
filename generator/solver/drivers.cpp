#include "solver/drivers.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <map>

#include "model/error.hpp"

namespace sweepgen::solver {

void DriverLayout::compose_all() {
  Track all{"composed", true, {}, {}};
  for (std::size_t i = 0; i < torques.size(); ++i) all.torques.push_back(i);
  for (std::size_t i = 0; i < external_forces.size(); ++i) all.external_forces.push_back(i);
  tracks = {all};
}

void DriverLayout::decompose_all() {
  tracks = {Track{"bias", true, {}, {}}};
  for (std::size_t i = 0; i < torques.size(); ++i) tracks.push_back(Track{torques[i], false, {i}, {}});
  for (std::size_t i = 0; i < external_forces.size(); ++i)
    tracks.push_back(Track{external_forces[i].name, false, {}, {i}});
}

std::vector<ConstraintSet> DriverLayout::constraint_sets() const {
  if (!sets.empty() || constraints == 0) return sets;
  return {ConstraintSet::on("", constraints)};
}

std::size_t DriverLayout::run_time_directions() const {
  std::size_t count = 0;
  for (const auto& set : constraint_sets())
    if (!set.directions_fixed()) count += set.count;
  return count;
}

std::size_t DriverLayout::listed_sets() const {
  std::size_t count = 0;
  for (const auto& set : sets) count += set.link.empty() ? 0 : 1;
  return count;
}

std::size_t DriverLayout::loop_sets() const {
  std::size_t count = 0;
  for (const auto& set : sets) count += set.relative() ? 1 : 0;
  return count;
}

bool DriverLayout::external_forces_separable() const {
  for (const auto& track : tracks)
    if (!track.external_forces.empty() && !track.only_external_forces()) return false;
  return true;
}

std::vector<std::string> direction_links(const DriverLayout& layout, const model::Chain& chain) {
  std::vector<std::string> links;
  for (const auto& set : layout.constraint_sets()) links.insert(links.end(), set.count, set.link_in(chain));
  return links;
}

std::vector<std::string> constraint_set_summary(const DriverLayout& layout) {
  const auto number = [](double v) {
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, v).ptr);
  };
  const auto range = [](std::size_t first, std::size_t count) {
    return count == 1 ? std::to_string(first) : std::to_string(first) + ".." + std::to_string(first + count - 1);
  };
  std::vector<std::string> lines;
  std::size_t first = 0, run_time = 0;
  for (std::size_t c = 0; c < layout.listed_sets(); ++c) {
    const ConstraintSet& set = layout.sets[c];
    const bool offset = set.at.E != model::Mat3::Identity() || set.at.r != model::Vec3::Zero();
    std::string line = "set " + std::to_string(c) + " on link " + inert_text(set.link) + (offset ? " (at an offset)" : "") +
                       (set.relative() ? " relative to link " + inert_text(set.relative_to) : "") + ": direction" +
                       (set.count == 1 ? " " : "s ") + range(first, set.count) + " (nu, beta), " +
                       (set.relative() ? "relative acceleration d/dt v_rel" : "link acceleration") + " set_acceleration[" +
                       range(6 * c, 6) + "]; ";
    if (set.directions_fixed()) {
      line += "fixed alpha";
      for (const auto& f : set.fixed) {
        line += " [";
        for (int i = 0; i < 6; ++i) line += (i ? ", " : "") + number(i < 3 ? f.moment[i] : f.force[i - 3]);
        line += "]";
      }
    } else {
      line += "alpha[" + range(run_time, set.count) + "] at run time";
      run_time += set.count;
    }
    lines.push_back(line);
    first += set.count;
  }
  return lines;
}

std::string structurally_overdetermined(const std::vector<ConstraintSet>& sets, const model::Chain& chain) {
  // Rows of the constraint Jacobian from sets on bodies B involve only the joints on the paths
  // from the base to B: more directions than those joints, for any group of sets, are always
  // rank-deficient (Hall's condition). Every group is tried, smallest first, up to 16 sets;
  // beyond, each set alone and all of them together.
  // Sets between two links are not judged here: their redundant directions are the rule
  // (redundant_loop_warnings, solver/shared_body_sets.hpp); their joints count for no group.
  const std::size_t count = sets.size();
  // The joints moving any of a group's sets, counted by which sets each joint moves: per joint on
  // a set's path to the base, the mask of the sets it moves; a group's joints are the joints whose
  // mask meets the group's. Time linear in the joints and sets, then per group in the masks
  // (at most two per set: a tree's paths share their trunks).
  static_assert(kMaxConstraints <= 32, "a set per bit of a mask");  // a set has a direction at least
  if (count > kMaxConstraints)
    return std::to_string(count) + " constraint sets, more than the " + std::to_string(kMaxConstraints) + " directions allowed";
  std::vector<std::uint32_t> moves(chain.dof() + 1, 0);
  for (std::size_t c = 0; c < count; ++c)
    for (std::size_t j = chain.frames.at(sets[c].link_in(chain)).body; j > 0 && !sets[c].relative(); j = chain.parent[j])
      moves[j] |= std::uint32_t{1} << c;
  std::map<std::uint32_t, std::size_t> joints_by_mask;
  for (std::size_t j = 1; j <= chain.dof(); ++j)
    if (moves[j] != 0) ++joints_by_mask[moves[j]];
  const auto check = [&](const std::vector<std::size_t>& group) -> std::string {
    std::uint32_t mask = 0;
    std::size_t directions = 0, joints = 0;
    for (std::size_t c : group) {
      if (sets[c].relative()) continue;
      directions += sets[c].count;
      mask |= std::uint32_t{1} << c;
    }
    for (const auto& [moved, number] : joints_by_mask) joints += (moved & mask) != 0 ? number : 0;
    if (directions <= joints) return "";
    std::string links;
    for (std::size_t c : group)
      if (!sets[c].relative()) links += (links.empty() ? "" : ", ") + quote_name(sets[c].link_in(chain));
    return std::to_string(directions) + " constraint direction" + (directions == 1 ? "" : "s") + " on link" +
           (group.size() == 1 ? " " : "s ") + links + " but only " + std::to_string(joints) + " joint" +
           (joints == 1 ? "" : "s") + " move" + (joints == 1 ? "s" : "") +
           " them: the constraint over-determines the robot (every state would be rank-deficient)";
  };
  std::vector<std::vector<std::size_t>> groups;
  if (count <= 16) {
    for (std::size_t mask = 1; mask < (std::size_t{1} << count); ++mask) {
      std::vector<std::size_t> group;
      for (std::size_t c = 0; c < count; ++c)
        if (mask & (std::size_t{1} << c)) group.push_back(c);
      groups.push_back(group);
    }
    std::stable_sort(groups.begin(), groups.end(), [](const auto& x, const auto& y) { return x.size() < y.size(); });
  } else {
    std::vector<std::size_t> all;
    for (std::size_t c = 0; c < count; ++c) groups.push_back({c}), all.push_back(c);
    groups.push_back(all);
  }
  for (const auto& group : groups)
    if (const std::string problem = check(group); !problem.empty()) return problem;
  return "";
}

std::string relative_to_problem(const ConstraintSet& set, const model::Chain& chain) {
  if (!set.relative()) return "";
  const auto other = chain.frames.find(set.relative_to);
  if (other == chain.frames.end()) {
    std::vector<std::string> links;
    for (const auto& [name, frame] : chain.frames) links.push_back(name);
    return "link " + quote_name(set.relative_to) + " is not on " + chain.extent() + nearest_name_hint(set.relative_to, links);
  }
  const auto own = chain.frames.find(set.link_in(chain));
  if (own == chain.frames.end() || own->second.body != other->second.body) return "";
  return "link " + quote_name(set.relative_to) + " rides on the same body as " + quote_name(set.link_in(chain)) +
         " (body " + quote_name(chain.bodies[own->second.body].link) +
         ", no moving joint between them on this chain; a link listed in 'tips' keeps the joints to it): "
         "the two never move apart";
}

std::string too_many_directions(const DriverLayout& layout, const model::Chain& chain) {
  if (layout.constraints + chain.couplings.size() <= kMaxConstraints) return "";
  return std::to_string(chain.couplings.size()) + " coupled <mimic> joints and " + std::to_string(layout.constraints) +
         " set directions: a solve holds at most " + std::to_string(kMaxConstraints) +
         " constraint directions, one per coupling among them (docs/derivation.md, M2); lock some of the <mimic> "
         "joints (locked_joints) or take them as joints of their own (mimic: independent)";
}

void validate(const DriverLayout& layout, const model::Chain& chain, const std::string& source) {
  std::vector<std::string> links;
  for (const auto& [name, frame] : chain.frames) links.push_back(name);
  std::size_t directions = 0;
  std::vector<std::string> set_links;
  for (const auto& set : layout.constraint_sets()) {
    const std::string& link = set.link_in(chain);
    const std::string element = "constraint set on " + quote_name(link);
    const auto frame = chain.frames.find(link);
    if (frame == chain.frames.end())
      throw InputError(source, element, "link " + quote_name(link) + " is not on " + chain.extent() + nearest_name_hint(link, links));
    if (frame->second.body == 0)
      throw InputError(source, element, "link " + quote_name(link) + " is fixed to the base; a constraint on it holds nothing");
    if (set.count == 0 || set.count > kMaxSetDirections)
      throw InputError(source, element, "a set holds 1..6 directions, got " + std::to_string(set.count));
    if (set.directions_fixed() && set.fixed.size() != set.count)
      throw InputError(source, element, std::to_string(set.fixed.size()) + " fixed directions for a set of " +
                                            std::to_string(set.count));
    if (set.link.empty() && layout.sets.size() > 1)
      throw InputError(source, element, "the tip set of the short form cannot be combined with listed sets");
    if (const std::string problem = relative_to_problem(set, chain); !problem.empty())
      throw InputError(source, element, "relative_to: " + problem);
    const std::string key = link + '\n' + set.relative_to;
    if (std::find(set_links.begin(), set_links.end(), key) != set_links.end())
      throw InputError(source, element, "a second set on the same link" + std::string(set.relative() ? "s" : "") +
                                            "; give one set with all its directions");
    set_links.push_back(key);
    directions += set.count;
  }
  if (directions != layout.constraints || directions > kMaxConstraints)
    throw InputError(source, "constraints", "the sets hold " + std::to_string(directions) + " directions, the layout says " +
                                                std::to_string(layout.constraints) + " (at most " +
                                                std::to_string(kMaxConstraints) + ")");
  if (const std::string problem = too_many_directions(layout, chain); !problem.empty())
    throw InputError(source, "mimic: coupled", problem);
  for (const auto& ext : layout.external_forces) {
    const std::string element = "external force " + quote_name(ext.name);
    const auto frame = chain.frames.find(ext.link);
    if (frame == chain.frames.end())
      throw InputError(source, element,
                       "link " + quote_name(ext.link) + " is not on " + chain.extent() + nearest_name_hint(ext.link, links));
    if (frame->second.body == 0)
      throw InputError(source, element, "link " + quote_name(ext.link) + " is fixed to the base; a force on it moves nothing");
  }
  std::vector<int> torque_uses(layout.torques.size()), external_uses(layout.external_forces.size());
  int bias_uses = 0;
  for (const auto& track : layout.tracks) {
    bias_uses += track.bias ? 1 : 0;
    for (auto i : track.torques) ++torque_uses.at(i);
    for (auto i : track.external_forces) ++external_uses.at(i);
  }
  const auto once = [&](int uses, const std::string& what) {
    if (uses != 1)
      throw InputError(source, "decomposition",
                       what + (uses == 0 ? " is on no track" : " is on more than one track"));
  };
  once(bias_uses, "the velocity-product bias");
  for (std::size_t i = 0; i < torque_uses.size(); ++i) once(torque_uses[i], "torque " + quote_name(layout.torques[i]));
  for (std::size_t i = 0; i < external_uses.size(); ++i)
    once(external_uses[i], "external force " + quote_name(layout.external_forces[i].name));
}

}  // namespace sweepgen::solver
