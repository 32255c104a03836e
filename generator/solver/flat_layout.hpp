// The flat-array entry points of a generated solver (templates/solver.hpp.mustache, `*_flat`):
// where each quantity sits in `in` and `out`, stated once for the emitter, the report, the
// benchmarks and the tests.
//   in  = [q (n; for a floating base: world_R_base row-major (9), then the n − 6 joints' positions),
//          q̇ (n), τff of each torque driver (n each), F_ext of each external-force driver
//          (6 each, [moment; force]), α (6 per constraint direction whose set the scene does not
//          fix, [moment; force], in its set's link frame), β = E_cstr (Nc)]
//   out = [q̈ (n), τcmd (n), τctrl (n), ν (Nc), Ẍ_tip (6, [angular; linear]),
//          Ẍ of each constraint set's link (6 each, only when the scene lists sets), status (1)]
#pragma once

#include <cstddef>
#include <vector>

#include "solver/drivers.hpp"
#include "solver/solve_inputs.hpp"

namespace sweepgen::solver {

struct FlatLayout {
  std::size_t dof = 0, constraints = 0;  // all `out` needs, with `sets`
  bool floating_base = false;  // q holds the base rotation, not the base's six coordinates (F5)
  std::size_t torques = 0, external_forces = 0;
  std::vector<std::size_t> input_directions;  // the constraint directions whose α is an input, in order
  std::size_t sets = 0;  // constraint sets listed by the scene (each reports its link's Ẍ)
  std::vector<std::size_t> direction_set;  // per constraint direction, its set (when `sets` > 0)

  static FlatLayout of(const DriverLayout& layout, std::size_t dof, bool floating_base) {
    FlatLayout flat{dof, layout.constraints, floating_base, layout.torques.size(), layout.external_forces.size(), {},
                    layout.listed_sets(), {}};
    std::size_t k = 0;
    const auto sets = layout.constraint_sets();
    for (std::size_t c = 0; c < sets.size(); ++c)
      for (std::size_t d = 0; d < sets[c].count; ++d, ++k) {
        if (!sets[c].directions_fixed()) flat.input_directions.push_back(k);
        flat.direction_set.push_back(c);
      }
    return flat;
  }

  // Offsets in `in`.
  std::size_t q() const { return 0; }
  std::size_t positions() const { return floating_base ? dof + 3 : dof; }  // values of q
  std::size_t qd() const { return positions(); }
  std::size_t torque(std::size_t t) const { return qd() + dof + t * dof; }
  std::size_t external_force(std::size_t e) const { return torque(torques) + 6 * e; }
  std::size_t alpha(std::size_t j) const { return external_force(external_forces) + 6 * j; }  // j-th input direction
  std::size_t beta() const { return alpha(input_directions.size()); }
  std::size_t in_size() const { return beta() + constraints; }
  // Offsets in `out`.
  std::size_t qdd() const { return 0; }
  std::size_t tau_cmd() const { return dof; }
  std::size_t tau_ctrl() const { return 2 * dof; }
  std::size_t nu() const { return 3 * dof; }
  std::size_t tip_acceleration() const { return nu() + constraints; }
  std::size_t set_acceleration(std::size_t c) const { return tip_acceleration() + 6 + 6 * c; }
  // Where direction k's link acceleration is: its set's, or Ẍ_tip when no sets are listed.
  std::size_t link_acceleration(std::size_t k) const {
    return sets == 0 ? tip_acceleration() : set_acceleration(direction_set.at(k));
  }
  std::size_t status() const { return set_acceleration(sets); }
  std::size_t out_size() const { return status() + 1; }
};

// The generated code's q: `q`, or for a floating base world_R_base row-major and the joints'
// positions q[6..] (F5).
std::vector<double> generated_positions(const JointVector<double>& q, const spatial::Mat3<double>& base_rotation,
                                        bool floating_base);

// `inputs` in the order of `layout` (α only of the directions in layout.input_directions).
std::vector<double> flat_input(const SolveInputs<double>& inputs, const FlatLayout& layout);

// A reference solution and its status written where a generated solver writes them in `out`.
template <class Scalar>
void flat_output(const Solution<Scalar>& solution, unsigned status, const FlatLayout& layout, Scalar* out) {
  for (std::size_t i = 0; i < layout.dof; ++i) {
    const auto at = static_cast<Eigen::Index>(i);
    out[layout.qdd() + i] = solution.qdd[at];
    out[layout.tau_cmd() + i] = solution.tau_cmd[at];
    out[layout.tau_ctrl() + i] = solution.tau_ctrl[at];
  }
  for (std::size_t k = 0; k < layout.constraints; ++k) out[layout.nu() + k] = solution.nu[static_cast<Eigen::Index>(k)];
  for (int c = 0; c < 3; ++c) {
    out[layout.tip_acceleration() + c] = solution.tip_acceleration.angular[c];
    out[layout.tip_acceleration() + 3 + c] = solution.tip_acceleration.linear[c];
  }
  for (std::size_t c = 0; c < layout.sets; ++c)
    for (int i = 0; i < 3; ++i) {
      out[layout.set_acceleration(c) + i] = solution.set_acceleration[c].angular[i];
      out[layout.set_acceleration(c) + 3 + i] = solution.set_acceleration[c].linear[i];
    }
  out[layout.status()] = static_cast<Scalar>(status);
}

}  // namespace sweepgen::solver
