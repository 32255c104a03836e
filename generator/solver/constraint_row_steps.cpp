#include "solver/constraint_row_steps.hpp"

#include <vector>

namespace sweepgen::solver {

ConstraintRowSteps constraint_row_steps(const model::Chain& chain, const DriverLayout& layout) {
  const std::size_t n = chain.dof();
  std::vector<std::size_t> depth(n + 1, 0);  // bodies from body i to the base, i included (0 for the base)
  for (std::size_t i = 1; i <= n; ++i) depth[i] = depth[chain.parent[i]] + 1;
  std::vector<bool> reaches(n + 1, false);  // body i or one beyond it carries a set
  ConstraintRowSteps steps;
  for (const ConstraintSet& set : layout.constraint_sets()) {
    for (const std::string* link : {&set.link_in(chain), set.relative() ? &set.relative_to : nullptr}) {
      if (link == nullptr) continue;  // (L4): a set between two links enters at both bodies
      const std::size_t body = chain.frames.at(*link).body;
      steps.inward_columns += set.count * depth[body];
      reaches[body] = true;
    }
  }
  for (std::size_t j = n; j >= 1; --j)
    if (reaches[j]) reaches[chain.parent[j]] = true;
  // Joint i's vector is at every body j beyond it (or i itself) that reaches a set: each such j
  // counts once per joint on its path to the base.
  for (std::size_t j = 1; j <= n; ++j)
    if (reaches[j]) steps.outward_rows += depth[j];
  return steps;
}

}  // namespace sweepgen::solver
