// The solver-sweep policies (paper Alg. 3, Alg. 4, Eq. 1) and what each one composes.
#pragma once

#include <optional>
#include <string>

#include "solver/drivers.hpp"

namespace sweepgen::solver {

enum class Policy {
  original,             // Alg. 3: every track enters E_conf and the articulated force
  prioritize_external,  // Alg. 4: the constraint does not react to external forces
  saturate,             // Eq. 1 as printed: τctrl clamped to the joint's effort limit
  saturate_exact,       // τcmd clamped to the effort limit, forward dynamics with it
};

inline const char* name(Policy policy) {
  switch (policy) {
    case Policy::original: return "original";
    case Policy::prioritize_external: return "prioritize_external";
    case Policy::saturate: return "saturate";
    case Policy::saturate_exact: return "saturate_exact";
  }
  return "";
}

inline std::optional<Policy> policy_from_name(const std::string& text) {
  for (Policy p : {Policy::original, Policy::prioritize_external, Policy::saturate, Policy::saturate_exact})
    if (text == name(p)) return p;
  return std::nullopt;
}

// Whether the solution under `policy` has a derivative (docs/derivation.md, (D3)): not for the
// saturating policies, whose clamp is a kink.
inline bool differentiable(Policy policy) { return policy == Policy::original || policy == Policy::prioritize_external; }

// Whether track `t` enters E_conf and the composed articulated force under `policy`.
inline bool composes(const Track& track, Policy policy) {
  return !(policy == Policy::prioritize_external && track.only_external_forces());
}

}  // namespace sweepgen::solver
