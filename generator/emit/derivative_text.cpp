#include "emit/derivative_text.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace sweepgen::emit {
namespace {

// The arrays of a derivative function's Derivatives, in the order of its flat output: the values,
// then the Jacobians the scene asks for (scene key derivatives).
std::vector<std::pair<std::string, std::size_t>> derivative_arrays(const solver::DerivativeColumns& derivative_columns,
                                                                   const solver::DerivativeOutputs& outputs) {
  const std::size_t n = derivative_columns.dof, nc = derivative_columns.constraints;
  const std::size_t columns = derivative_columns.count();
  std::vector<std::pair<std::string, std::size_t>> arrays = {
      {"qdd", n}, {"nu", nc}, {"tau_cmd", n}, {"d_qdd", outputs.qdd ? n * columns : 0},
      {"d_nu", outputs.nu ? nc * columns : 0}, {"d_tau_cmd", outputs.tau_cmd ? n * columns : 0}};
  arrays.erase(std::remove_if(arrays.begin(), arrays.end(), [](const auto& a) { return a.second == 0; }), arrays.end());
  return arrays;
}

}  // namespace

std::string derivative_flat_out(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs) {
  std::string text;
  for (const auto& [name, size] : derivative_arrays(columns, outputs))
    text += name + " (" + (name.rfind("d_", 0) == 0 ? std::string(name == "d_nu" ? "constraints" : "dof") + " x derivative_columns"
                                                     : std::string(name == "nu" ? "constraints" : "dof")) + "), ";
  return text + "status";
}

std::string pack_derivatives(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs) {
  std::string text = "  S* cursor_out = out;\n";
  for (const auto& [name, size] : derivative_arrays(columns, outputs))
    text += "  SWEEPGEN_UNROLLED for (int i = 0; i < " + std::to_string(size) + "; ++i) *cursor_out++ = derivatives." + name + "[i];\n";
  return text + "  *cursor_out = Lanes<S>::value(derivatives.status);";
}

std::string derivatives_line(const solver::DerivativeOutputs& outputs, std::size_t nc) {
  const std::pair<const char*, bool> jacobians[] = {{"qdd", outputs.qdd}, {"nu", outputs.nu}, {"tau_cmd", outputs.tau_cmd}};
  std::string returned, left_out;
  for (const auto& [name, with] : jacobians) {
    if (std::string(name) == "nu" && nc == 0) continue;
    std::string& list = with ? returned : left_out;
    list += (list.empty() ? "" : ", ") + std::string(name);
  }
  return "Derivatives: derivatives_<policy> return the Jacobians of " + returned +
         (left_out.empty() ? std::string(" (scene: derivatives)") : " (scene: derivatives); not computed: " + left_out);
}

std::string check_derivatives(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs) {
  std::string text = "  S residue{};  // NaN/Inf among the results (scene: check_inputs; see outward())\n";
  for (const auto& [name, size] : derivative_arrays(columns, outputs))
    text += "  SWEEPGEN_UNROLLED for (int i = 0; i < " + std::to_string(size) + "; ++i) residue += out." + name + "[i] - out." + name +
            "[i];\n";
  return text + "  status |= Lanes<S>::status_if(residue != 0, status_not_finite);";
}

}  // namespace sweepgen::emit
