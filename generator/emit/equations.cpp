#include "emit/equations.hpp"

#include <map>
#include <stdexcept>

namespace sweepgen::emit {

const Equation& equation_of(const std::string& array) {
  static const std::map<std::string, Equation> table = {
      {"X_E", {"outward", "X_i = X_J(q_i) X_T: rotation E"}},
      {"X_r", {"outward", "X_i = X_J(q_i) X_T: translation r"}},
      {"velocity", {"outward", "Xd_i = X_i Xd_{i-1} + S_i qd_i"}},
      {"bias_acceleration", {"outward", "Xddb_i = Xd_i x (S_i qd_i)"}},
      {"bias_force", {"outward", "Fb_i = Xd_i x* (M_i Xd_i)"}},
      {"articulated_inertia", {"inward", "M^A_{i-1} = M_{i-1} + X_i^T P_i^T M^A_i X_i   [A | B | C blocks]"}},
      {"U", {"inward", "U_i = M^A_i S_i"}},
      {"D", {"inward", "D_i = d_i + S_i^T M^A_i S_i"}},
      {"inverse_D", {"inward", "D_i^-1, 0 where the joint is locked (D_i <= tol (d_i + tr block of M^A_i))"}},
      {"locked", {"inward", "1 where D_i <= tol (d_i + tr block of M^A_i): joint locked"}},
      {"constraint_force", {"inward", "F^A_cstr,i-1 = X_i^T P_i^T F^A_cstr,i   [column k: 6k..6k+5]"}},
      {"constraint_energy", {"inward", "E^A_cstr,i-1 = E^A_cstr,i + F^A_cstr,i^T S_i D_i^-1 S_i^T F^A_cstr,i"}},
      {"articulated_force", {"inward", "F^A_t,i-1 = own_t,i-1 + X_i^T (Fc + U_i D_i^-1 u),  u = tau_t,i - S_i^T Fc"}},
      {"acceleration_energy", {"inward", "E^A_t,i-1 = E^A_t,i + F^A_cstr,i^T (Xddb_i [bias] + S_i D_i^-1 u)"}},
      {"nu", {"solver", "nu = S x, (S E^A_cstr,0 S [+ tol I]) x = S (E_cstr - F^A_cstr,0^T Xdd_0 - E_conf): equilibrated LDL^T, pivoted or damped"}},
      {"conf_energy", {"solver", "E_conf = sum over composed tracks of E^A_t,0"}},
      {"locked_joints", {"solver", "joints locked by the joint-inertia policy (status_joint_inertia_singular)"}},
      {"dropped_pivots", {"solver", "pivots of E^A_cstr,0 below tolerance (status_constraint_rank_deficient)"}},
      {"tau_ctrl", {"solver", "tau_ctrl_i = S_i^T F^A_cstr,i nu  (+ external share, Alg. 4; clamped, Eq. 1)"}},
      {"qdd", {"solver", "qdd_i = D_i^-1 (tau_ff_i + tau_ctrl_i - S_i^T (F^A_i + M^A_i (X_i Xdd_{i-1} + Xddb_i)))"}},
      {"acceleration", {"solver", "Xdd_i = X_i Xdd_{i-1} + Xddb_i + S_i qdd_i"}},
      {"tip_acceleration", {"solver", "Xdd_tip = X_tip Xdd_N"}},
      {"tau_cmd", {"solver", "tau_cmd = tau_ff + J^T (F_cstr nu)  (RNEA of qdd for Eq. 1; clamped for exact saturation)"}},
      {"saturated", {"solver", "1 where the policy clamped joint i's torque"}},
      {"correction_force", {"solver", "F^A of the clamped extra torque (exact saturation)"}},
  };
  std::string key = array;
  for (const char* prefix : {"articulated_force", "acceleration_energy"})
    if (array.rfind(prefix, 0) == 0) key = prefix;
  const auto found = table.find(key);
  if (found == table.end()) throw std::logic_error("no equation recorded for array '" + array + "'");
  return found->second;
}

}  // namespace sweepgen::emit
