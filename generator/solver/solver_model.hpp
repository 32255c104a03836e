// The chain's constants in the solver's scalar: what every sweep reads and never writes.
// For the symbolic scalar these become folded constants of the generated code.
#pragma once

#include <cmath>
#include <vector>

#include "model/chain.hpp"
#include "model/joint_inertia_bounds.hpp"
#include "solver/drivers.hpp"
#include "solver/joint_transform_tangent.hpp"
#include "solver/scalar_ops.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::solver {

using spatial::Force;
using spatial::Inertia;
using spatial::Mat3;
using spatial::Motion;
using spatial::Transform;
using spatial::Vec3;

// How ν is solved from E^A_cstr,0 (solver/constraint_multipliers.hpp, docs/stability.md):
// both work on E equilibrated by exact powers of two, both are scale-invariant.
enum class ConstraintFactorisation {
  pivoted_ldlt,  // drop a direction whose pivot is <= tol (relative): exact where kept
  damped,        // damped least squares (Ê + tol I): every direction kept, biased by ~tol cond
};

// How the inward sweep forms the rows r_i = S_i^T F^A_cstr,i that (I3), (I5), (S3) need
// (docs/derivation.md, (I6)): through the Nc columns F^A_cstr,i (I2), or outward from each joint
// to the constrained links without forming the columns. The reference solver forms the columns
// unless asked; the generator counts both and emits the cheaper (scene key constraint_rows).
enum class ConstraintRows {
  inward_columns,  // (I2): the columns F^A_cstr,i, body by body from the constrained links inward
  outward_rows,    // (I6): S_i carried outward through P_j X_j to each constrained link
};

struct SolverOptions {
  model::Vec3 gravity{0, 0, -9.81};  // in the root link's frame, or the world's for a floating base [m/s^2]
  ConstraintFactorisation constraint_factorisation = ConstraintFactorisation::pivoted_ldlt;
  // Relative tolerance of the E^A_cstr,0 factorisation (docs/derivation.md, "Singular
  // constraints"): the pivot threshold (pivoted_ldlt) or the damping (damped), both relative to
  // the equilibrated diagonal; <= 0 picks default_pivot_tolerance(epsilon of the scalar).
  double pivot_tolerance = 0;
  // Relative tolerance of the joint-inertia policy (solver/joint_inertia.hpp): joint i is locked
  // when D_i <= t (d_i + tr of its block of M^A_i); <= 0 picks 1000 epsilon of the scalar.
  double joint_inertia_tolerance = 0;
  // One step of iterative refinement of ν from the constraint's residual (R1) in the policies
  // that enforce the constraint exactly (original, and saturate_exact before its clamp) with
  // the pivoted factorisation.
  bool refinement = true;
  ConstraintRows constraint_rows = ConstraintRows::inward_columns;

  static double default_pivot_tolerance(double epsilon) { return 1000 * epsilon; }
  double pivot_tolerance_for(double epsilon) const {
    return pivot_tolerance > 0 ? pivot_tolerance : default_pivot_tolerance(epsilon);
  }
  double joint_inertia_tolerance_for(double epsilon) const {
    return joint_inertia_tolerance > 0 ? joint_inertia_tolerance : 1000 * epsilon;
  }
};

template <class Scalar>
struct JointModel {
  model::JointType type = model::JointType::revolute;
  Transform<Scalar> tree_transform;  // X_T
  Motion<Scalar> S;                  // motion subspace in the body frame
  // Revolute joints: E_J(q) = axis_outer + cos q (1 − axis_outer) − sin q [axis]×,
  // written so that axis-aligned joints fold to plain rotations.
  Mat3<Scalar> axis_outer, axis_complement, axis_skew;
  Vec3<Scalar> axis;
  Scalar rotor_inertia;  // d_i
  Scalar effort_limit;   // used by the saturating policies
  bool floating_base_coordinate = false;  // held at q = 0, no velocity-product term (F5, O2)
  // (J2): false where the bounds of model/joint_inertia_bounds.hpp prove that (J1) never locks
  // the joint; then D_i^-1 = 1 / D_i without a test.
  bool can_lock = true;
  // (J2): k where the joint never locks, d_i = 0 and S_i = ±e_k in its angular (revolute) or
  // linear (prismatic) part: the k-th component of P_i^T F is then exactly 0; else -1.
  int exact_zero_component = -1;
  // A coupled <mimic> joint (M1): its index in SolverModel::couplings, -1 for a joint of its own.
  int coupling = -1;

  // X_i = X_J(q) X_T, the motion transform from body λ(i) to body i (F2); X_T for a floating
  // base's coordinate, which is held at q = 0 (F5).
  Transform<Scalar> transform(const Scalar& q) const {
    using std::cos;
    using std::sin;
    Transform<Scalar> joint;
    if (floating_base_coordinate) return tree_transform;
    if (type == model::JointType::revolute) {
      joint.E = axis_outer + axis_complement * cos(q) - axis_skew * sin(q);
    } else {
      joint.r = axis * q;
    }
    return with_joint_tangent(joint * tree_transform, S, q);  // (D6) where Scalar carries tangents
  }
};

// Where a constraint set acts: the body its link rides on and the motion transform from that
// body's frame to the set's frame A; its directions are first .. first + count - 1. A set between
// two links (L1) also names the body its second link rides on, the transform from that body to
// frame B (B's pose enters the pose error only: ^AX_B Ẍ_B is ^AX_b Ẍ_b whatever B), and the two
// bodies' nearest common ancestor, through which the outward sweep composes ^AX_b.
template <class Scalar>
struct ConstraintSetModel {
  std::size_t body = 0;
  Transform<Scalar> frame;
  std::size_t first = 0, count = 0;
  bool relative = false;
  std::size_t other_body = 0;
  Transform<Scalar> other_frame;
  std::size_t common_ancestor = 0;
};

// A coupled <mimic> joint (model::JointCoupling): one constraint direction of its own (M2).
template <class Scalar>
struct JointCouplingModel {
  std::size_t joint = 0, source = 0;  // 1..N
  Scalar multiplier, offset;          // q_joint = multiplier q_source + offset
};

template <class Scalar>
struct SolverModel {
  std::vector<JointModel<Scalar>> joints;  // 0..N, [0] unused
  std::vector<Inertia<Scalar>> inertia;    // M_i, 0..N, [0] unused
  std::vector<std::size_t> parent;         // λ(i) < i, 0..N (model::Chain::parent)
  Transform<Scalar> tip;                   // body N -> tip link frame
  std::vector<std::size_t> external_force_body;        // per external-force instance
  std::vector<Transform<Scalar>> external_force_frame; // body -> link of that instance
  std::vector<ConstraintSetModel<Scalar>> constraint_sets;
  std::vector<std::size_t> constraint_set_of;          // per direction k of the sets, its set
  // The coupled <mimic> joints, directions set_directions() .. constraints() - 1 (M2).
  std::vector<JointCouplingModel<Scalar>> couplings;
  Vec3<Scalar> gravity;                    // g in the root link's (fixed) or the world's (floating) frame
  bool floating_base = false;              // Ẍ_0 = −[0; Rᵀ g] at run time (O4, F5), else −[0; g]
  ConstraintFactorisation constraint_factorisation = ConstraintFactorisation::pivoted_ldlt;
  Scalar pivot_tolerance;
  Scalar joint_inertia_tolerance;
  bool refinement = true;
  ConstraintRows constraint_rows = ConstraintRows::inward_columns;
  DriverLayout layout;
  // (C5): per constraint set, the body nearest the base that carries it and no other set, where its
  // block of E^A_cstr,0's lower bound is complete; empty where (C5) does not apply
  // (private_blocks_tops).
  std::vector<std::size_t> private_top;

  std::size_t dof() const { return joints.size() - 1; }
  std::size_t base_coordinates() const { return floating_base ? 6 : 0; }
  // Every constraint direction: the sets' (Nc, those of β and ν), then one per coupling.
  std::size_t constraints() const { return layout.constraints + couplings.size(); }
  std::size_t set_directions() const { return layout.constraints; }
  bool has_relative_sets() const {
    for (const ConstraintSetModel<Scalar>& set : constraint_sets)
      if (set.relative) return true;
    return false;
  }
  const ConstraintSetModel<Scalar>& set_of(std::size_t direction) const {
    return constraint_sets[constraint_set_of[direction]];
  }

  // `epsilon`: machine epsilon of the arithmetic the solver will run in (for the default
  // pivot tolerance; the symbolic scalar passes the emitted scalar's).
  SolverModel(const model::Chain& chain, const DriverLayout& drivers, const SolverOptions& options, double epsilon)
      : layout(drivers) {
    const std::size_t n = chain.dof();
    joints.resize(n + 1);
    inertia.resize(n + 1);
    parent = chain.parent;
    for (std::size_t i = 1; i <= n; ++i) {
      const model::Joint& j = chain.joints[i];
      JointModel<Scalar>& jm = joints[i];
      jm.type = j.type;
      jm.tree_transform = j.tree_transform.cast<Scalar>();
      const bool revolute = j.type == model::JointType::revolute;
      (revolute ? jm.S.angular : jm.S.linear) = j.axis.cast<Scalar>();
      const model::Mat3 outer = j.axis * j.axis.transpose();
      jm.axis_outer = outer.cast<Scalar>();
      jm.axis_complement = (model::Mat3::Identity() - outer).cast<Scalar>();
      jm.axis_skew = spatial::skew(j.axis).cast<Scalar>();
      jm.axis = j.axis.cast<Scalar>();
      jm.rotor_inertia = Scalar(j.rotor_inertia);
      jm.effort_limit = Scalar(j.effort_limit);
      jm.floating_base_coordinate = j.floating_base_coordinate;
      inertia[i] = chain.bodies[i].inertia.cast<Scalar>();
    }
    for (const model::JointCoupling& coupling : chain.couplings) {
      joints[coupling.joint].coupling = static_cast<int>(couplings.size());
      couplings.push_back({coupling.joint, coupling.source, Scalar(coupling.multiplier), Scalar(coupling.offset)});
    }
    tip = chain.tip().X.cast<Scalar>();
    for (const auto& ext : layout.external_forces) {
      const model::Frame& frame = chain.frames.at(ext.link);
      external_force_body.push_back(frame.body);
      external_force_frame.push_back(frame.X.cast<Scalar>());
    }
    for (const auto& set : layout.constraint_sets()) {
      const model::Frame& frame = chain.frames.at(set.link_in(chain));
      for (std::size_t k = 0; k < set.count; ++k) constraint_set_of.push_back(constraint_sets.size());
      ConstraintSetModel<Scalar> placed;
      placed.body = frame.body;
      placed.frame = (set.at * frame.X).cast<Scalar>();
      placed.first = constraint_set_of.size() - set.count;
      placed.count = set.count;
      if (set.relative()) {
        const model::Frame& other = chain.frames.at(set.relative_to);
        placed.relative = true;
        placed.other_body = other.body;
        placed.other_frame = (set.relative_at * other.X).cast<Scalar>();
        placed.common_ancestor = frame.body;
        while (!model::supports(parent, placed.common_ancestor, other.body))
          placed.common_ancestor = parent[placed.common_ancestor];
      }
      constraint_sets.push_back(placed);
    }
    floating_base = chain.floating_base;
    gravity = options.gravity.cast<Scalar>();
    constraint_factorisation = options.constraint_factorisation;
    pivot_tolerance = Scalar(options.pivot_tolerance_for(epsilon));
    const double lock_tolerance = options.joint_inertia_tolerance_for(epsilon);
    joint_inertia_tolerance = Scalar(lock_tolerance);
    const std::vector<model::JointInertiaBounds> joint_bounds = model::joint_inertia_bounds(chain);
    for (std::size_t i = 1; i <= n; ++i) {
      // (J2): a margin of 2 over (J1)'s rule keeps the rounding of the computed D_i and of its
      // threshold (a few ε of the scale, against a tolerance of 1000 ε by default) from mattering.
      const model::JointInertiaBounds& bounds = joint_bounds[i];
      JointModel<Scalar>& jm = joints[i];
      jm.can_lock = !(bounds.lower > 2 * lock_tolerance * bounds.upper);
      if (jm.can_lock || chain.joints[i].rotor_inertia != 0) continue;
      for (int k = 0; k < 3; ++k)
        if (std::abs(chain.joints[i].axis[k]) == 1) jm.exact_zero_component = k;
    }
    refinement = options.refinement;
    constraint_rows = options.constraint_rows;
    if (constraint_factorisation == ConstraintFactorisation::pivoted_ldlt) private_top = private_blocks_tops(chain);
  }

  // (C5) applies where there are two constraint sets or more and each reaches the base through at
  // least as many joints of its own (joints that carry no other set) as it has directions: only
  // then can every block of B be nonsingular (the quadruped's feet: three leg joints each; the
  // dual Panda's hands: seven). Per set, the last of those joints' bodies towards the base.
  std::vector<std::size_t> private_blocks_tops(const model::Chain& chain) const {
    std::vector<std::size_t> tops;
    if (constraint_sets.size() < 2) return tops;
    // A set between two links is carried up two paths, a coupling acts at two joints; a block
    // would be complete only where they meet. Not taken: (C4)'s own test decides (the same
    // answer, docs/derivation.md (C5)).
    if (!couplings.empty()) return tops;
    for (const ConstraintSetModel<Scalar>& set : constraint_sets)
      if (set.relative) return tops;
    for (std::size_t c = 0; c < constraint_sets.size(); ++c) {
      std::size_t top = 0, own_joints = 0;
      for (std::size_t b = constraint_sets[c].body; b != 0; b = chain.parent[b]) {
        bool alone = true;
        for (std::size_t d = 0; d < constraint_sets.size(); ++d)
          if (d != c && model::supports(chain.parent, b, constraint_sets[d].body)) alone = false;
        if (!alone) break;
        top = b;
        ++own_joints;
      }
      if (own_joints < constraint_sets[c].count) return {};
      tops.push_back(top);
    }
    return tops;
  }
};

}  // namespace sweepgen::solver
