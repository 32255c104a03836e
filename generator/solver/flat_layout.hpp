// The flat-array entry points of a generated solver (templates/solver.hpp.mustache, `*_flat`):
// where each quantity sits in `in` and `out`, stated once for the emitter, the report, the
// benchmarks and the tests.
//   in  = [q (n), q̇ (n), τff of each torque driver (n each), F_ext of each external-force driver
//          (6 each, [moment; force]), α (6 per constraint direction, [moment; force], only when
//          the scene does not fix the directions), β = E_cstr (Nc)]
//   out = [q̈ (n), τcmd (n), τctrl (n), ν (Nc), Ẍ_tip (6, [angular; linear]), status (1)]
#pragma once

#include <cstddef>
#include <vector>

#include "solver/drivers.hpp"
#include "solver/solve_inputs.hpp"

namespace sweepgen::solver {

struct FlatLayout {
  std::size_t dof = 0, constraints = 0;  // all `out` needs
  std::size_t torques = 0, external_forces = 0;
  bool directions_in_input = false;  // α is an input (the scene does not fix it)

  static FlatLayout of(const DriverLayout& layout, std::size_t dof, bool fixed_directions) {
    return {dof, layout.constraints, layout.torques.size(), layout.external_forces.size(),
            !fixed_directions && layout.constraints > 0};
  }

  // Offsets in `in`.
  std::size_t q() const { return 0; }
  std::size_t qd() const { return dof; }
  std::size_t torque(std::size_t t) const { return 2 * dof + t * dof; }
  std::size_t external_force(std::size_t e) const { return torque(torques) + 6 * e; }
  std::size_t alpha(std::size_t k) const { return external_force(external_forces) + 6 * k; }  // directions_in_input
  std::size_t beta() const { return alpha(directions_in_input ? constraints : 0); }
  std::size_t in_size() const { return beta() + constraints; }
  // Offsets in `out`.
  std::size_t qdd() const { return 0; }
  std::size_t tau_cmd() const { return dof; }
  std::size_t tau_ctrl() const { return 2 * dof; }
  std::size_t nu() const { return 3 * dof; }
  std::size_t tip_acceleration() const { return nu() + constraints; }
  std::size_t status() const { return tip_acceleration() + 6; }
  std::size_t out_size() const { return status() + 1; }
};

// `inputs` in the order of `layout` (α left out when the scene fixes it).
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
  out[layout.status()] = static_cast<Scalar>(status);
}

}  // namespace sweepgen::solver
