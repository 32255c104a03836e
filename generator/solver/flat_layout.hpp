// The flat-array entry points of a generated solver (templates/solver.hpp.mustache, `*_flat`):
// where each quantity sits in `in` and `out`, stated once for the emitter, the report, the
// benchmarks and the tests.
//   in  = [q (n; for a floating base: world_R_base row-major (9), then the n − 6 joints' positions;
//          without the coupled <mimic> joints, M1), q̇ (n, without the coupled joints), τff of each
//          torque driver (n each, every joint), F_ext of each external-force driver
//          (6 each, [moment; force]), α (6 per constraint direction whose set the scene does not
//          fix, [moment; force], in its set's link frame), β = E_cstr (Nc)]
//   out = [q̈ (n), τcmd (n), τctrl (n), ν (Nc), the coupled joints' transmission torques (one
//          each, M2), Ẍ_tip (6, [angular; linear]),
//          Ẍ of each constraint set's link (6 each, only when the scene lists sets), the closure
//          error of each set between two links (12 each: pose error (L3), v_rel (L1)), status (1)],
//          each of the first eight only where the scene's `outputs` lists it (SolveOutputs)
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "model/chain.hpp"
#include "solver/drivers.hpp"
#include "solver/solve_inputs.hpp"

namespace sweepgen::solver {

// The results a solve returns (scene key `outputs`, default all of them): the generated code
// computes what the listed ones need and writes only them; status is always returned.
struct SolveOutputs {
 private:
  template <class Self>
  static auto* flag_of(Self& self, const std::string& array) {
    for (auto [name, value] : {std::pair{"qdd", &self.qdd}, {"tau_cmd", &self.tau_cmd}, {"tau_ctrl", &self.tau_ctrl},
                               {"nu", &self.nu}, {"tip_acceleration", &self.tip_acceleration},
                               {"set_acceleration", &self.set_acceleration}, {"closure_error", &self.closure_error},
                               {"coupling_torque", &self.coupling_torque}})
      if (array == name) return value;
    return static_cast<decltype(&self.qdd)>(nullptr);
  }

 public:
  bool qdd = true, tau_cmd = true, tau_ctrl = true, nu = true, tip_acceleration = true, set_acceleration = true,
       closure_error = true, coupling_torque = true;

  // The flag of the Solution array `array` (state_fields.hpp), nullptr for one that is not listable.
  bool* flag(const std::string& array) { return flag_of(*this, array); }
  bool lists(const std::string& array) const {
    const bool* value = flag_of(*this, array);
    return value != nullptr && *value;
  }
  bool all() const {
    return qdd && tau_cmd && tau_ctrl && nu && tip_acceleration && set_acceleration && closure_error && coupling_torque;
  }
};

struct FlatLayout {
  std::size_t dof = 0, constraints = 0;  // all `out` needs, with `sets`
  bool floating_base = false;  // q holds the base rotation, not the base's six coordinates (F5)
  std::size_t torques = 0, external_forces = 0;
  std::vector<std::size_t> input_directions;  // the constraint directions whose α is an input, in order
  std::size_t sets = 0;  // constraint sets listed by the scene (each reports its link's Ẍ)
  std::vector<std::size_t> direction_set;  // per constraint direction, its set (when `sets` > 0)
  SolveOutputs outputs;  // which of them `out` holds
  std::size_t loops = 0;  // constraint sets between two links (each reports its closure error)
  std::vector<model::JointCoupling> couplings;  // the coupled <mimic> joints (M1): no q, q̇ of their own

  static FlatLayout of(const DriverLayout& layout, std::size_t dof, bool floating_base,
                       const SolveOutputs& outputs = {}, std::vector<model::JointCoupling> couplings = {}) {
    FlatLayout flat{dof, layout.constraints, floating_base, layout.torques.size(), layout.external_forces.size(), {},
                    layout.listed_sets(), {}, outputs, layout.loop_sets(), std::move(couplings)};
    std::size_t k = 0;
    const auto sets = layout.constraint_sets();
    for (std::size_t c = 0; c < sets.size(); ++c)
      for (std::size_t d = 0; d < sets[c].count; ++d, ++k) {
        if (!sets[c].directions_fixed()) flat.input_directions.push_back(k);
        flat.direction_set.push_back(c);
      }
    return flat;
  }
  static FlatLayout of(const DriverLayout& layout, const model::Chain& chain, const SolveOutputs& outputs = {}) {
    return of(layout, chain.dof(), chain.floating_base, outputs, chain.couplings);
  }

  // Offsets in `in`.
  std::size_t q() const { return 0; }
  std::size_t velocities() const { return dof - couplings.size(); }  // values of q̇
  std::size_t positions() const { return floating_base ? velocities() + 3 : velocities(); }  // values of q
  std::size_t qd() const { return positions(); }
  std::size_t torque(std::size_t t) const { return qd() + velocities() + t * dof; }
  std::size_t external_force(std::size_t e) const { return torque(torques) + 6 * e; }
  std::size_t alpha(std::size_t j) const { return external_force(external_forces) + 6 * j; }  // j-th input direction
  std::size_t beta() const { return alpha(input_directions.size()); }
  std::size_t in_size() const { return beta() + constraints; }
  // Offsets in `out` (of the outputs listed; an unlisted one takes no room).
  std::size_t qdd() const { return 0; }
  std::size_t tau_cmd() const { return qdd() + (outputs.qdd ? dof : 0); }
  std::size_t tau_ctrl() const { return tau_cmd() + (outputs.tau_cmd ? dof : 0); }
  std::size_t nu() const { return tau_ctrl() + (outputs.tau_ctrl ? dof : 0); }
  std::size_t coupling_torque() const { return nu() + (outputs.nu ? constraints : 0); }
  std::size_t tip_acceleration() const { return coupling_torque() + (outputs.coupling_torque ? couplings.size() : 0); }
  std::size_t set_acceleration(std::size_t c) const { return tip_acceleration() + (outputs.tip_acceleration ? 6 : 0) + 6 * c; }
  // Whether `out` holds direction k's link acceleration: its set's, or Ẍ_tip when no sets are listed.
  bool has_link_acceleration() const { return sets == 0 ? outputs.tip_acceleration : outputs.set_acceleration; }
  std::size_t link_acceleration(std::size_t k) const {
    return sets == 0 ? tip_acceleration() : set_acceleration(direction_set.at(k));
  }
  std::size_t closure_error(std::size_t c) const { return set_acceleration(outputs.set_acceleration ? sets : 0) + 12 * c; }
  std::size_t status() const { return closure_error(outputs.closure_error ? loops : 0); }
  std::size_t out_size() const { return status() + 1; }
};

// The generated code's q: `q`, or for a floating base world_R_base row-major and the joints'
// positions q[6..] (F5); without the joints of `couplings` (M1).
std::vector<double> generated_positions(const JointVector<double>& q, const spatial::Mat3<double>& base_rotation,
                                        bool floating_base, const std::vector<model::JointCoupling>& couplings = {});
// The generated code's q̇: `qd` without the joints of `couplings` (M1).
std::vector<double> generated_velocities(const JointVector<double>& qd, const std::vector<model::JointCoupling>& couplings);
// q and q̇ with each coupled joint's entries those its source gives it (M1): q_m = k q_s + o, q̇_m = k q̇_s.
void follow_couplings(JointVector<double>& q, JointVector<double>& qd, const std::vector<model::JointCoupling>& couplings);
// q and q̇ of all `dof` joints from the generated code's values (generated_positions without a
// floating base's rotation, generated_velocities): a floating base's six q 0 (F5), each coupled
// joint's from its source (follow_couplings).
void joint_values_from_generated(const double* positions, const double* velocities, std::size_t dof, bool floating_base,
                                 const std::vector<model::JointCoupling>& couplings, JointVector<double>& q,
                                 JointVector<double>& qd);

// `inputs` in the order of `layout` (α only of the directions in layout.input_directions).
std::vector<double> flat_input(const SolveInputs<double>& inputs, const FlatLayout& layout);

// The inputs `in` holds in the order of `flat` (flat_input's inverse): the directions the scene
// fixes come from `drivers`, a floating base's rotation from its nine values (its six
// coordinates in q are 0: not read, F5).
SolveInputs<double> solve_inputs_from_flat(const double* in, const FlatLayout& flat, const DriverLayout& drivers);

// A reference solution and its status written where a generated solver writes them in `out`.
template <class Scalar>
void flat_output(const Solution<Scalar>& solution, unsigned status, const FlatLayout& layout, Scalar* out) {
  const SolveOutputs& listed = layout.outputs;
  for (std::size_t i = 0; i < layout.dof; ++i) {
    const auto at = static_cast<Eigen::Index>(i);
    if (listed.qdd) out[layout.qdd() + i] = solution.qdd[at];
    if (listed.tau_cmd) out[layout.tau_cmd() + i] = solution.tau_cmd[at];
    if (listed.tau_ctrl) out[layout.tau_ctrl() + i] = solution.tau_ctrl[at];
  }
  for (std::size_t k = 0; listed.nu && k < layout.constraints; ++k)
    out[layout.nu() + k] = solution.nu[static_cast<Eigen::Index>(k)];
  for (std::size_t c = 0; listed.coupling_torque && c < layout.couplings.size(); ++c)
    out[layout.coupling_torque() + c] = solution.nu[static_cast<Eigen::Index>(layout.constraints + c)];
  for (int c = 0; listed.tip_acceleration && c < 3; ++c) {
    out[layout.tip_acceleration() + c] = solution.tip_acceleration.angular[c];
    out[layout.tip_acceleration() + 3 + c] = solution.tip_acceleration.linear[c];
  }
  for (std::size_t c = 0; listed.set_acceleration && c < layout.sets; ++c)
    for (int i = 0; i < 3; ++i) {
      out[layout.set_acceleration(c) + i] = solution.set_acceleration[c].angular[i];
      out[layout.set_acceleration(c) + 3 + i] = solution.set_acceleration[c].linear[i];
    }
  for (std::size_t c = 0; listed.closure_error && c < layout.loops; ++c)
    for (std::size_t half = 0; half < 2; ++half)
      for (int i = 0; i < 3; ++i) {
        out[layout.closure_error(c) + 6 * half + i] = solution.closure_error[c][half].angular[i];
        out[layout.closure_error(c) + 6 * half + 3 + i] = solution.closure_error[c][half].linear[i];
      }
  out[layout.status()] = static_cast<Scalar>(status);
}

}  // namespace sweepgen::solver
