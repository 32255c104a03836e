#include "model/chain.hpp"

namespace sweepgen::model {

std::size_t Chain::joint_index(const std::string& name) const {
  for (std::size_t i = 1; i < joints.size(); ++i)
    if (joints[i].name == name) return i;
  return 0;
}

}  // namespace sweepgen::model
