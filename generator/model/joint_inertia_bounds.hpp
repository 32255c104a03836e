// Bounds, valid at every configuration, on the two quantities the joint-inertia policy (J1)
// compares (docs/derivation.md, (J2)): the joint-space inertia D_i = d_i + S_i^T M^A_i S_i and its
// scale d_i + tr(block of M^A_i that S_i reads). Where lower > 2 tol upper, (J1) can never lock
// joint i, and the solver drops the test (solver/joint_inertia.hpp).
//
// Lower: M^A_i is M_i plus positive semi-definite terms from the children (each a projected
// articulated inertia, I1), so D_i >= d_i + S_i^T M_i S_i, the body's own inertia about or along
// the joint. Upper: a projected articulated inertia is at most the unprojected one, so M^A_i is
// at most the composite rigid inertia of the subtree, whose trace is bounded body by body:
// revolute, tr of the rotational block about body i's origin, tr A_k + 2 m_k R (2 |c_k| + R) for
// body k with centre of mass c_k (in its frame) and origin at most R from body i's (R: the sum of
// the joint offsets |r| of X_T on the path, plus a prismatic joint's largest |limit|; revolute
// joints keep distances from their own origin); prismatic, tr C = 3 m per body.
#pragma once

#include <cstddef>
#include <vector>

#include "model/chain.hpp"

namespace sweepgen::model {

struct JointInertiaBounds {
  double lower = 0;  // <= d_i + S_i^T M^A_i S_i
  double upper = 0;  // >= d_i + tr of the block S_i reads; Inf where a prismatic joint below has no limit
};

// Per joint 1..N (entry 0 unused), in one pass from the tips inwards: time linear in the bodies.
std::vector<JointInertiaBounds> joint_inertia_bounds(const Chain& chain);

}  // namespace sweepgen::model
