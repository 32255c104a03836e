#include "model/joint_inertia_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sweepgen::model {
namespace {

// How far body j's origin can be from its parent's: |r| of X_T, plus the travel of a prismatic
// joint (its largest |limit|; Inf without limits). A floating base's coordinates are held at 0 (F5).
double largest_offset(const Joint& joint) {
  const double offset = joint.tree_transform.r.norm();
  if (joint.type == JointType::revolute || joint.floating_base_coordinate) return offset;
  return offset + std::max(std::abs(joint.lower), std::abs(joint.upper));
}

// The subtree of a body, seen from an origin at most d_k from each body k's (the largest offsets
// of the joints between): its bodies' tr A_k, |h_k| and m_k (h = m c, the first moment) summed, and
// |h_k| d_k, m_k d_k, m_k d_k^2 summed. Every term is >= 0: moving the origin out by one more
// offset adds to each, nothing cancels. `reach_infinite`: some body of it lies past a prismatic
// joint without limits.
struct Subtree {
  double trace = 0, first_moment = 0, mass = 0, first_moment_reach = 0, mass_reach = 0, mass_reach2 = 0;
  double translational_trace = 0;  // tr C_k = 3 m_k summed
  bool reach_infinite = false;

  // The same bodies seen from `offset` further (the parent's origin).
  Subtree moved_by(double offset) const {
    Subtree s = *this;
    if (std::isinf(offset)) {
      s.reach_infinite = true;
      return s;
    }
    s.mass_reach2 += offset * (2 * mass_reach + offset * mass);
    s.first_moment_reach += offset * first_moment;
    s.mass_reach += offset * mass;
    return s;
  }
  void add(const Subtree& o) {
    trace += o.trace;
    first_moment += o.first_moment;
    mass += o.mass;
    first_moment_reach += o.first_moment_reach;
    mass_reach += o.mass_reach;
    mass_reach2 += o.mass_reach2;
    translational_trace += o.translational_trace;
    reach_infinite = reach_infinite || o.reach_infinite;
  }
  // Sum over the bodies of tr A_k + 2 R_k (2 |h_k| + m_k R_k), the bound of tr of the rotational
  // block about the origin (J2).
  double rotational_trace_bound() const {
    if (reach_infinite) return std::numeric_limits<double>::infinity();
    return trace + 4 * first_moment_reach + 2 * mass_reach2;
  }
};

}  // namespace

std::vector<JointInertiaBounds> joint_inertia_bounds(const Chain& chain) {
  const std::size_t n = chain.dof();
  // Bodies from the tips inwards (λ(i) < i): each body's subtree about its own origin, then seen
  // from its parent's, one pass.
  std::vector<Subtree> subtree(n + 1);
  for (std::size_t i = n; i >= 1; --i) {
    const Inertia& body = chain.bodies[i].inertia;
    Subtree own;
    own.mass = body.C.trace() / 3;
    own.first_moment = Vec3(body.B(2, 1), body.B(0, 2), body.B(1, 0)).norm();  // B = h×
    own.trace = body.A.trace();
    own.translational_trace = body.C.trace();
    subtree[i].add(own);
    if (chain.parent[i] != 0) subtree[chain.parent[i]].add(subtree[i].moved_by(largest_offset(chain.joints[i])));
  }
  std::vector<JointInertiaBounds> bounds(n + 1);
  for (std::size_t i = 1; i <= n; ++i) {
    const Joint& joint = chain.joints[i];
    const bool revolute = joint.type == JointType::revolute;
    const Inertia& own = chain.bodies[i].inertia;
    bounds[i].lower = joint.rotor_inertia + joint.axis.dot((revolute ? own.A : own.C) * joint.axis);
    bounds[i].upper =
        joint.rotor_inertia + (revolute ? subtree[i].rotational_trace_bound() : subtree[i].translational_trace);
  }
  return bounds;
}

}  // namespace sweepgen::model
