#include "emit/equations.hpp"

#include <map>
#include <stdexcept>

namespace sweepgen::emit {

const Equation& equation_of(const std::string& array) {
  static const std::map<std::string, Equation> table = {
      {"X_E", {"outward", "rotation E of X_i = X_J(q_i) X_T,i", "F2"}},
      {"X_r", {"outward", "translation r of X_i = X_J(q_i) X_T,i", "F2"}},
      {"velocity", {"outward", "body velocity Xd_i", "O1"}},
      {"bias_acceleration", {"outward", "bias acceleration Xddb_i", "O2"}},
      {"bias_force", {"outward", "bias force Fb_i", "O3"}},
      {"loop_X_E", {"outward", "rotation E of ^AX_b of each set between two links   [set s: 9s..9s+8]", "L1"}},
      {"loop_X_r", {"outward", "translation r of ^AX_b of each set between two links   [set s: 3s..3s+2]", "L1"}},
      {"relative_velocity", {"outward", "v_rel = v_A - ^AX_b Xd_b of each set between two links   [set s: 6s..6s+5]", "L1"}},
      {"velocity_product", {"outward", "v_A x ^AX_b Xd_b of each set between two links   [set s: 6s..6s+5]", "L1, L5"}},
      {"articulated_inertia", {"inward", "articulated inertia M^A_{i-1}   [A | B | C blocks]", "I1"}},
      {"U", {"inward", "U_i = M^A_i S_i", "I0"}},
      {"D", {"inward", "joint-space inertia D_i", "I0"}},
      {"inverse_D", {"inward", "D_i^-1, 0 where joint i is locked", "J1"}},
      {"locked", {"inward", "1 where joint i is locked", "J1"}},
      {"constraint_force", {"inward", "unit constraint forces F^A_cstr,i-1   [column k: 6k..6k+5]", "I2"}},
      {"constraint_row", {"inward", "rows r_i = S_i^T F^A_cstr,i of the constraint forces", "I2, I6"}},
      {"constraint_energy", {"inward", "constraint-space matrix E^A_cstr,i-1", "I3"}},
      {"base_acceleration_energy", {"inward", "what the base acceleration adds, F^A_cstr,0^T Xdd_0", "S2, I6"}},
      {"articulated_force", {"inward", "articulated force F^A_t,i-1 of the track", "I4"}},
      {"acceleration_energy", {"inward", "acceleration energy E^A_t,i-1 of the track", "I5"}},
      {"nu", {"solver", "constraint multipliers nu: equilibrated E^A_cstr,0 factored as the file header says", "S2, C1, C2, C3, C4"}},
      {"coupling_torque", {"solver", "transmission torque of each coupled <mimic> joint: its direction's nu", "M2, S2"}},
      {"conf_energy", {"solver", "composed acceleration energy E_conf", "S1"}},
      {"locked_joints", {"solver", "number of joints locked (status_joint_inertia_singular)", "J1"}},
      {"dropped_pivots", {"solver", "number of constraint directions not enforced (status_constraint_rank_deficient)", "C2, C3, C4"}},
      {"tau_ctrl", {"solver", "constraint torque tau_ctrl_i", "S3"}},
      {"qdd", {"solver", "joint acceleration qdd_i", "S4"}},
      {"acceleration", {"solver", "body acceleration Xdd_i", "S5"}},
      {"tip_acceleration", {"solver", "tip acceleration Xdd_tip", "S5"}},
      {"set_acceleration", {"solver", "acceleration of each constraint set's link, in its frame [set c: 6c..6c+5]", "S5"}},
      {"closure_error", {"solver", "closure error of each set between two links: pose error, v_rel [set c: 12c..12c+11]", "L1, L3"}},
      {"tau_cmd", {"solver", "commanded torque tau_cmd", "T1, T2, X1"}},
      {"saturated", {"solver", "whether the policy clamped joint i's torque", "S3, X1"}},
      {"correction_force", {"solver", "articulated force of the clamped extra torque", "X1"}},
      {"frame_E", {"residual", "rotation E of ^iX_c, body i's transform from the coordinates c", "D8"}},
      {"frame_r", {"residual", "translation r of ^iX_c", "D8"}},
      {"frame_axis", {"residual", "joint axis S_i in the coordinates c", "D8"}},
      {"frame_velocity", {"residual", "body velocity Xd_i in the coordinates c", "D8, O1"}},
      {"frame_axis_rate", {"residual", "Sd_i = Xd_parent x S_i", "D8"}},
      {"frame_acceleration", {"residual", "body acceleration Xdd_i of the solution, in the coordinates c", "D8, S5"}},
      {"composite_inertia", {"residual", "composite inertia Y_i of the subtree   [A | B | C blocks]", "D8"}},
      {"composite_coriolis", {"residual", "Coriolis composite Q_i of the subtree   [T | s]", "D8"}},
      {"composite_momentum", {"residual", "composite momentum H_i of the subtree", "D8"}},
      {"composite_force", {"residual", "force F_i the subtree needs, less the wrenches on it", "D8, T1, T2"}},
      {"acceleration_along_q", {"residual", "a_i, what Xdd past joint i gains along q_i beyond the turn", "D8"}},
      {"acceleration_along_qd", {"residual", "psi_i, what Xdd past joint i gains along qd_i beyond S_i x Xd", "D8"}},
      {"inertia_on_axis", {"residual", "g_i = Y_i S_i", "D8"}},
      {"coriolis_on_axis", {"residual", "k_i = Q_i S_i + S_i x* H_i", "D8"}},
      {"force_along_q", {"residual", "U_i, what F moves along q_i (rows of the joints carrying joint i)", "D8"}},
      {"force_along_qd", {"residual", "V_i, what F moves along qd_i (rows of the joints carrying joint i)", "D8"}},
      {"d_rho", {"residual", "Jacobian of the joints' residuals rho, row j at [j * 2N]: q columns, then qd", "D5, D8"}},
      {"d_r", {"residual", "Jacobian of the constraints' residuals r, row k at [k * 2N]: q columns, then qd", "D5, D8"}},
      {"d_qdd", {"derivative", "Jacobian of qdd, row r at [r * derivative_columns], columns q, qd, tau_ff, beta", "D1, D2, D3"}},
      {"d_nu", {"derivative", "Jacobian of nu, row k at [k * derivative_columns], columns q, qd, tau_ff, beta", "D1, D2, D3"}},
      {"d_tau_cmd", {"derivative", "Jacobian of tau_cmd, row r at [r * derivative_columns], columns q, qd, tau_ff, beta", "D1, D2, D3"}},
  };

  std::string key = array;
  for (const char* prefix : {"articulated_force", "acceleration_energy"})
    if (array.rfind(prefix, 0) == 0) key = prefix;
  const auto found = table.find(key);
  if (found == table.end()) throw std::logic_error("no equation recorded for array '" + array + "'");
  return found->second;
}

}  // namespace sweepgen::emit
