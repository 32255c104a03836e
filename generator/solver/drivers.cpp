#include "solver/drivers.hpp"

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

bool DriverLayout::external_forces_separable() const {
  for (const auto& track : tracks)
    if (!track.external_forces.empty() && !track.only_external_forces()) return false;
  return true;
}

void validate(const DriverLayout& layout, const model::Chain& chain, const std::string& source) {
  if (layout.constraints > kMaxConstraints)
    throw InputError(source, "constraints", "at most 6 end-effector constraint directions, got " +
                                                std::to_string(layout.constraints));
  std::vector<std::string> links;
  for (const auto& [name, frame] : chain.frames) links.push_back(name);
  for (const auto& ext : layout.external_forces) {
    const std::string element = "external force " + quote_name(ext.name);
    const auto frame = chain.frames.find(ext.link);
    if (frame == chain.frames.end())
      throw InputError(source, element,
                       "link " + quote_name(ext.link) + " is not on the chain" + nearest_name_hint(ext.link, links));
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
