// The stability suite's test-only helpers (docs/stability.md): the CI/full switch and exact
// power-of-two scaled copies. The cases and the scale-invariant errors are shared with
// `sweepgen report --stability` (report/stability_cases.hpp, report/stability_errors.hpp).
#pragma once

#include <cmath>
#include <cstdlib>
#include <string>

#include "report/measure.hpp"
#include "report/stability_cases.hpp"
#include "scene/scene.hpp"

namespace sweepgen::test {

// SWEEPGEN_STABILITY_FULL=1: the heavy cases (100 and 300 joints) and every state count in full
// (docs/stability.md); otherwise the CI reduction.
inline bool stability_full() {
  const char* full = std::getenv("SWEEPGEN_STABILITY_FULL");
  return full != nullptr && std::string(full) == "1";
}

// ---- Exact power-of-two scaling -------------------------------------------------------------
// Lengths by 2^a, masses by 2^b (time unchanged): every quantity scales by a power of two,
// so in binary floating point the scaled problem is the original one with shifted exponents.
// Units: length L, mass M. Revolute: q̇, q̈ unchanged, torques M L². Prismatic: q, q̇, q̈ L,
// forces M L. Wrenches: moment M L², force M L. Gravity L. Inertia blocks A: M L², B: M L,
// C: M. Rotor inertia: M L² (revolute), M (prismatic).
struct Scaling {
  int length = 0, mass = 0;
  double L() const { return std::ldexp(1.0, length); }
  double M() const { return std::ldexp(1.0, mass); }
  double torque(const model::Joint& j) const {
    return j.type == model::JointType::revolute ? M() * L() * L() : M() * L();
  }
  double motion(const model::Joint& j) const { return j.type == model::JointType::revolute ? 1.0 : L(); }
};

inline model::Chain scaled(model::Chain c, const Scaling& k) {
  for (std::size_t i = 1; i <= c.dof(); ++i) {
    model::Joint& j = c.joints[i];
    j.rotor_inertia *= j.type == model::JointType::revolute ? k.M() * k.L() * k.L() : k.M();
    j.effort_limit *= k.torque(j);
    j.tree_transform.r *= k.L();
    if (j.type == model::JointType::prismatic) {
      j.lower *= k.L();
      j.upper *= k.L();
    }
    model::Inertia& I = c.bodies[i].inertia;
    I.A *= k.M() * k.L() * k.L();
    I.B *= k.M() * k.L();
    I.C *= k.M();
    c.bodies[i].mass *= k.M();
  }
  for (auto& [link, frame] : c.frames) frame.X.r *= k.L();
  return c;
}

// The scene in the scaled units: gravity by L, fixed directions as α below.
inline scene::Scene scaled(scene::Scene s, const Scaling& k) {
  s.gravity *= k.L();
  for (auto& set : s.layout.sets)
    for (auto& a : set.fixed) a.force /= k.L();
  return s;
}

// The same state in the scaled units. α_k = [n; f] becomes [n; f / L] (so that α_k^T Ẍ is
// unchanged: Ẍ's linear part scales by L), β unchanged; then ν scales by M L².
inline report::Problem scaled(report::Problem p, const model::Chain& chain, const scene::Scene& s, const Scaling& k) {
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const Eigen::Index j = static_cast<Eigen::Index>(i - 1);
    p.q[j] *= k.motion(chain.joints[i]);
    p.qd[j] *= k.motion(chain.joints[i]);
    p.tau_ff[j] *= k.torque(chain.joints[i]);
    for (auto& t : p.torques) t[j] *= k.torque(chain.joints[i]);
  }
  for (auto& w : p.wrenches) {
    w.moment *= k.M() * k.L() * k.L();
    w.force *= k.M() * k.L();
  }
  for (auto& a : p.alpha) a.force /= k.L();
  report::pack_flat(s, chain, p);
  return p;
}

}  // namespace sweepgen::test
