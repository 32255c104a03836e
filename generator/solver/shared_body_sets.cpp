#include "solver/shared_body_sets.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "model/error.hpp"

namespace sweepgen::solver {

std::vector<std::string> shared_body_warnings(const std::vector<ConstraintSet>& sets, const model::Chain& chain) {
  // Sets against the world by the body they act on; sets between two links by their pair of bodies
  // (either way round): each group constrains one body's motion, or one body's relative to another.
  constexpr std::size_t kWorld = static_cast<std::size_t>(-1);
  std::map<std::pair<std::size_t, std::size_t>, std::vector<std::size_t>> sets_on_body;
  for (std::size_t c = 0; c < sets.size(); ++c) {
    const std::size_t body = chain.frames.at(sets[c].link_in(chain)).body;
    const std::size_t other = sets[c].relative() ? chain.frames.at(sets[c].relative_to).body : kWorld;
    sets_on_body[{std::min(body, other), std::max(body, other)}].push_back(c);
  }
  std::vector<std::string> warnings;
  for (const auto& [bodies, on_body] : sets_on_body) {
    if (on_body.size() < 2) continue;
    const std::size_t body = bodies.second == kWorld ? bodies.first : chain.frames.at(sets[on_body.front()].link_in(chain)).body;
    std::string links;
    std::size_t directions = 0;
    for (std::size_t c : on_body) {
      links += (links.empty() ? "" : ", ") + std::string("set ") + std::to_string(c) + " on " +
               quote_name(sets[c].link_in(chain)) +
               (sets[c].relative() ? " relative to " + quote_name(sets[c].relative_to) : "");
      directions += sets[c].count;
    }
    warnings.push_back(
        "constraint sets act on one rigid body: " + links + " are all carried by the body of link " +
        quote_name(chain.bodies[body].link) +
        (bodies.second == kWorld
             ? ""
             : " (relative to the body of link " +
                   quote_name(chain.bodies[bodies.first == body ? bodies.second : bodies.first].link) + ")") +
        " (the joints between them are fixed or locked), so their " + std::to_string(directions) +
        " directions constrain that one body's acceleration together: more than six, or forces at several points "
        "(three at each of two points span five), are dependent, and every such solve reports "
        "status_constraint_rank_deficient; put the sets on links a moving joint separates (for a gripper's "
        "fingers: the scene key tips), or give one set on one of the links");
  }
  return warnings;
}

std::vector<std::string> redundant_loop_warnings(const std::vector<ConstraintSet>& sets, const model::Chain& chain) {
  std::vector<std::string> warnings;
  for (std::size_t c = 0; c < sets.size(); ++c) {
    if (!sets[c].relative()) continue;
    // The joints on one link's path to the base and not on the other's move the two apart.
    std::vector<int> on_path(chain.dof() + 1, 0);
    for (const std::string* link : {&sets[c].link_in(chain), &sets[c].relative_to})
      for (std::size_t j = chain.frames.at(*link).body; j > 0; j = chain.parent[j]) on_path[j] ^= 1;
    std::size_t joints = 0;
    for (int moved : on_path) joints += static_cast<std::size_t>(moved);
    if (sets[c].count <= joints) continue;
    warnings.push_back("set " + std::to_string(c) + " on " + quote_name(sets[c].link_in(chain)) + " relative to " +
                       quote_name(sets[c].relative_to) + " holds " + std::to_string(sets[c].count) + " directions but only " +
                       std::to_string(joints) + " joint" + (joints == 1 ? "" : "s") + " move the two links apart: " +
                       std::to_string(sets[c].count - joints) + " or more are redundant at every state and dropped, "
                       "status_constraint_rank_deficient on every solve (a planar loop closed by a 3-D or 6-D set; "
                       "leave the directions out that the mechanism cannot violate to have an ok status)");
  }
  return warnings;
}

}  // namespace sweepgen::solver
