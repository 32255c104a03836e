#include "solver/shared_body_sets.hpp"

#include <map>

#include "model/error.hpp"

namespace sweepgen::solver {

std::vector<std::string> shared_body_warnings(const std::vector<ConstraintSet>& sets, const model::Chain& chain) {
  std::map<std::size_t, std::vector<std::size_t>> sets_on_body;
  for (std::size_t c = 0; c < sets.size(); ++c) sets_on_body[chain.frames.at(sets[c].link_in(chain)).body].push_back(c);
  std::vector<std::string> warnings;
  for (const auto& [body, on_body] : sets_on_body) {
    if (on_body.size() < 2) continue;
    std::string links;
    std::size_t directions = 0;
    for (std::size_t c : on_body) {
      links += (links.empty() ? "" : ", ") + std::string("set ") + std::to_string(c) + " on " +
               quote_name(sets[c].link_in(chain));
      directions += sets[c].count;
    }
    warnings.push_back(
        "constraint sets act on one rigid body: " + links + " are all carried by the body of link " +
        quote_name(chain.bodies[body].link) +
        " (the joints between them are fixed or locked), so their " + std::to_string(directions) +
        " directions constrain that one body's acceleration together: more than six, or forces at several points "
        "(three at each of two points span five), are dependent, and every such solve reports "
        "status_constraint_rank_deficient; put the sets on links a moving joint separates (for a gripper's "
        "fingers: the scene key tips), or give one set on one of the links");
  }
  return warnings;
}

}  // namespace sweepgen::solver
