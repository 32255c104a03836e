#include "model/joint_inertia_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sweepgen::model {
namespace {

// How far body j's origin can be from its parent's: |r| of X_T, plus the travel of a prismatic
// joint (its largest |limit|; Inf without limits). A floating base's coordinates are held at 0 (F5).
double largest_offset(const Joint& joint) {
  const double offset = joint.tree_transform.r.norm();
  if (joint.type == JointType::revolute || joint.floating_base_coordinate) return offset;
  return offset + std::max(std::abs(joint.lower), std::abs(joint.upper));
}

// Body k's contribution to tr of the rotational block, about an origin at most `reach` away
// from its own: tr A_k + 2 m R (2 |c| + R) = tr A_k + 2 R (2 |h| + m R), h = m c its first moment.
double rotational_trace_bound(const Inertia& body, double reach) {
  const double mass = body.C.trace() / 3;
  const Vec3 h(body.B(2, 1), body.B(0, 2), body.B(1, 0));  // B = h×
  const double moved = reach == 0 ? 0.0 : 2 * reach * (2 * h.norm() + mass * reach);
  return body.A.trace() + moved;
}

}  // namespace

JointInertiaBounds joint_inertia_bounds(const Chain& chain, std::size_t i) {
  const Joint& joint = chain.joints[i];
  const bool revolute = joint.type == JointType::revolute;
  const Inertia& own = chain.bodies[i].inertia;
  JointInertiaBounds bounds;
  bounds.lower = joint.rotor_inertia + joint.axis.dot((revolute ? own.A : own.C) * joint.axis);
  bounds.upper = joint.rotor_inertia;
  for (std::size_t k = i; k < chain.bodies.size(); ++k) {
    if (!chain.supports(i, k)) continue;
    const Inertia& body = chain.bodies[k].inertia;
    if (!revolute) {
      bounds.upper += body.C.trace();
      continue;
    }
    double reach = 0;
    for (std::size_t j = k; j != i; j = chain.parent[j]) reach += largest_offset(chain.joints[j]);
    bounds.upper += std::isinf(reach) ? std::numeric_limits<double>::infinity() : rotational_trace_bound(body, reach);
  }
  return bounds;
}

}  // namespace sweepgen::model
