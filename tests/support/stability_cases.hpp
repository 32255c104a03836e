// The cases of the numerical-stability suite (docs/stability.md): the synthetic family
// (generator/family, written to a scratch directory and loaded through the normal scene and
// URDF loaders) and the bundled scenes, each with the configuration where its six tip
// directions are singular; exact power-of-two scaled copies; scale-invariant errors.
#pragma once

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "family/family.hpp"
#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "support/bundled_robots.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen::test {

// SWEEPGEN_STABILITY_FULL=1: the heavy cases (100 and 300 joints) and every state count in full
// (docs/stability.md); otherwise the CI reduction.
inline bool stability_full() {
  const char* full = std::getenv("SWEEPGEN_STABILITY_FULL");
  return full != nullptr && std::string(full) == "1";
}

struct StabilityCase {
  std::string name;
  scene::Scene scene;
  model::Chain chain;
  std::vector<double> singular_q;  // empty: none known
  bool heavy = false;
};

// Writes the family case into `dir` and loads it like any scene.
inline StabilityCase family_stability_case(const std::string& name, const TempDir& dir) {
  const family::FamilyCase c = family::family_case(name);
  dir.write(name + ".urdf", family::urdf_text(c.robot));
  StabilityCase s{name, scene::load_scene(dir.write(name + ".yaml", family::scene_text(c))), {}, c.singular_q, c.heavy};
  s.chain = scene::load_scene_chain(s.scene);
  return s;
}

// The bundled scenes with six constraint directions, and the planar robot's two. q = 0 is
// singular for all three arms (stretched; panda and iiwa: joints 1, 3, 5, 7 on one line; UR5:
// elbow straight and wrist axes 4 and 6 aligned); the tests check it through cond(E^A_cstr,0).
inline StabilityCase bundled_stability_case(const std::string& scene_file, bool singular_at_zero) {
  StabilityCase s{scene_file, scene::load_scene(source_path(scene_file)), {}, {}, false};
  s.name = s.scene.solver;
  s.chain = scene::load_scene_chain(s.scene);
  if (singular_at_zero) s.singular_q.assign(s.chain.dof(), 0.0);
  return s;
}

inline std::vector<std::string> bundled_stability_scenes() {
  return {"robots/panda/panda_nc6.yaml", "robots/iiwa14/iiwa14_nc6.yaml", "robots/ur5/ur5_nc6.yaml",
          "robots/planar/planar_nc2.yaml"};
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
  for (auto& a : s.fixed_directions) a.force /= k.L();
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
  report::pack_flat(s, p);
  return p;
}

// ---- Scale-invariant errors -------------------------------------------------------------------
// ‖a − b‖∞ / ‖b‖∞ over the revolute joints and over the prismatic joints separately (their
// units differ), the larger of the two; a group whose b is 0 counts ‖a‖∞ (0 when exact). No
// floor in SI units: the figure is the same for a robot in any units. Infinity for NaN/Inf.
// `also`: further vectors whose size counts in the scale (the terms b is the sum of: where they
// cancel, rounding is relative to them, not to b).
inline double joint_relative_error(const std::vector<report::Precise>& a, const std::vector<report::Precise>& b,
                                   const model::Chain& chain,
                                   const std::vector<std::vector<report::Precise>>& also = {}) {
  double worst = 0;
  for (const auto type : {model::JointType::revolute, model::JointType::prismatic}) {
    report::Precise diff = 0, scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (chain.joints[i + 1].type != type) continue;
      if (!isfinite(a[i])) return INFINITY;
      diff = std::max(diff, abs(a[i] - b[i]));
      scale = std::max(scale, abs(b[i]));
      for (const auto& v : also) scale = std::max(scale, abs(v[i]));
    }
    worst = std::max(worst, static_cast<double>(scale > report::Precise(0) ? diff / scale : diff));
  }
  return worst;
}

// ‖a − b‖∞ / ‖b‖∞ (ν: one unit for all entries).
inline double vector_relative_error(const std::vector<report::Precise>& a, const std::vector<report::Precise>& b) {
  report::Precise diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!isfinite(a[i])) return INFINITY;
    diff = std::max(diff, abs(a[i] - b[i]));
    scale = std::max(scale, abs(b[i]));
  }
  return static_cast<double>(scale > report::Precise(0) ? diff / scale : diff);
}

}  // namespace sweepgen::test
