// The values of one solve's inputs (q, q̇, the drivers, β), in any scalar: what the report and
// the tests hand to the reference solver (ReferenceSolver::run) and, through flat_input
// (flat_layout.hpp), to a generated solver.
#pragma once

#include <vector>

#include "solver/state.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::solver {

template <class Scalar>
struct SolveInputs {
  JointVector<Scalar> q, qd;  // N each; a floating base's first six q are not read (F5)
  std::vector<JointVector<Scalar>> torques;      // one per torque driver
  std::vector<spatial::Force<Scalar>> wrenches;  // one per external-force driver, its link's frame
  std::vector<spatial::Force<Scalar>> alpha;     // Nc directions, tip frame (fixed ones too)
  ConstraintVector<Scalar> beta;                 // Nc setpoints E_cstr
  // world_R_base (base coordinates -> world) of a floating base, whose gravity it turns (O4);
  // not read for a fixed base.
  spatial::Mat3<Scalar> base_rotation = spatial::Mat3<Scalar>::Identity();

  template <class To>
  SolveInputs<To> cast() const {
    const auto force = [](const spatial::Force<Scalar>& f) {
      return spatial::Force<To>{f.moment.template cast<To>(), f.force.template cast<To>()};
    };
    SolveInputs<To> to{q.template cast<To>(), qd.template cast<To>(), {}, {}, {}, beta.template cast<To>(),
                       base_rotation.template cast<To>()};
    for (const auto& t : torques) to.torques.push_back(t.template cast<To>());
    for (const auto& w : wrenches) to.wrenches.push_back(force(w));
    for (const auto& a : alpha) to.alpha.push_back(force(a));
    return to;
  }
};

}  // namespace sweepgen::solver
