#include "emit/struct_text.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "emit/equations.hpp"
#include "emit/names.hpp"
#include "model/inert_text.hpp"

namespace sweepgen::emit {
namespace {

// One array of the Drivers struct: its declarator, the loop header(s) over its values, the
// element those loops reach and what it holds; its name, how many values of the flat input it
// takes (`dof_values` times dof, plus `fixed_values`), and whether it is rows of six (α).
struct DriverArray {
  std::string declarator, loops, element, doc;
  std::string name;
  std::size_t dof_values = 0, fixed_values = 0;
  bool rows = false;
};

// The extent of the run-time α: `constraints` when every direction is an input.
std::string alpha_extent(const solver::DriverLayout& layout) {
  const std::size_t inputs = layout.run_time_directions();
  return inputs == layout.constraints ? "constraints" : std::to_string(inputs);
}

std::vector<DriverArray> driver_arrays(const symbolic::TraceRequest& request) {
  std::vector<DriverArray> arrays;
  for (const auto& name : request.layout.torques)
    arrays.push_back({name + "[dof]", "for (int i = 0; i < dof; ++i)", name + "[i]", "feed-forward joint torques", name, 1, 0});
  for (const auto& ext : request.layout.external_forces)
    arrays.push_back({ext.name + "[6]", "for (int i = 0; i < 6; ++i)", ext.name + "[i]",
                      "wrench [moment; force] on link " + inert_text(ext.link) + ", in its frame", ext.name, 0, 6});
  const solver::DriverLayout& layout = request.layout;
  if (layout.run_time_directions() > 0) {
    const std::string extent = alpha_extent(layout);
    arrays.push_back({"alpha[" + extent + "][6]", "for (int k = 0; k < " + extent + "; ++k)\n    for (int i = 0; i < 6; ++i)",
                      "alpha[k][i]",
                      layout.listed_sets() == 0 ? "constraint directions [moment; force], tip frame, unit norm"
                                          : "run-time constraint directions [moment; force], each in its set's link frame, "
                                            "unit norm (sets: see the file header)",
                      "alpha", 0, 6 * layout.run_time_directions(), true});
  }
  return arrays;
}

// The Solution arrays the solves return (scene key outputs), in the order of solver::FlatLayout's
// `out` (solver/flat_layout.hpp), with their extents and loop headers (ν without constraints:
// named, with no entries).
struct SolutionArray {
  std::string name, extent, element, loop;
};
std::vector<SolutionArray> solution_arrays(const solver::SolveOutputs& outputs, std::size_t sets, std::size_t loops,
                                           std::size_t couplings) {
  std::vector<SolutionArray> arrays;
  const std::string joints = "for (int i = 0; i < dof; ++i)";
  for (const char* name : {"qdd", "tau_cmd", "tau_ctrl"})
    if (outputs.lists(name)) arrays.push_back({name, "dof", name + std::string("[i]"), joints});
  if (outputs.nu) arrays.push_back({"nu", "constraints", "nu[k]", "for (int k = 0; k < constraints; ++k)"});
  if (couplings > 0 && outputs.coupling_torque)
    arrays.push_back({"coupling_torque", "couplings", "coupling_torque[c]", "for (int c = 0; c < couplings; ++c)"});
  if (outputs.tip_acceleration) arrays.push_back({"tip_acceleration", "6", "tip_acceleration[i]", "for (int i = 0; i < 6; ++i)"});
  if (sets > 0 && outputs.set_acceleration) {
    const std::string n = std::to_string(6 * sets);
    arrays.push_back({"set_acceleration", "6 per constraint set", "set_acceleration[i]", "for (int i = 0; i < " + n + "; ++i)"});
  }
  if (loops > 0 && outputs.closure_error) {
    const std::string n = std::to_string(12 * loops);
    arrays.push_back({"closure_error", "12 per set between two links", "closure_error[i]", "for (int i = 0; i < " + n + "; ++i)"});
  }
  return arrays;
}

// Loop headers whose body moves or checks one value, each marked to be unrolled (SWEEPGEN_UNROLLED,
// templates/lanes.mustache: a Batch's values then stay in registers).
std::string unrolled(const std::string& loops) {
  std::string text;
  std::size_t from = 0;
  for (std::size_t at = loops.find("for ("); at != std::string::npos; from = at, at = loops.find("for (", at + 1))
    text += loops.substr(from, at - from) + "SWEEPGEN_UNROLLED ";
  return text + loops.substr(from);
}

}  // namespace

std::string array_members(const symbolic::Trace& trace, const std::vector<std::size_t>& fields, std::size_t bodies,
                          bool solution, const MemberTypes& types) {
  std::vector<std::string> order;
  std::map<std::string, std::pair<bool, int>> shape;  // name -> (per body, components)
  for (std::size_t i : fields) {
    const auto& f = trace.fields[i];
    auto [it, inserted] = shape.emplace(f.array, std::make_pair(f.body >= 0, 0));
    if (inserted) order.push_back(f.array);
    it->second.second = std::max(it->second.second, f.component + 1);
  }
  std::string text;
  for (const auto& name : order) {
    const auto& [per_body, components] = shape[name];
    const Storage storage = solution ? solution_storage(name) : Storage::value;
    const std::string extent = storage == Storage::count ? ""
                               : (per_body ? "[" + std::to_string(bodies) + "]" : "") + "[" + std::to_string(components) + "]";
    const std::string& type = storage == Storage::flag ? types.flag : storage == Storage::count ? types.count : types.value;
    text += "  " + type + " " + name + extent + ";  // " + equation_of(name).cited() + "\n";
  }
  return text;
}

std::string drivers_members(const symbolic::TraceRequest& request, const std::string& type) {
  std::string text;
  for (const auto& a : driver_arrays(request)) text += "  " + type + " " + a.declarator + ";  // " + a.doc + "\n";
  return text;
}

std::string flat_drivers_members(const symbolic::TraceRequest& request) {
  std::string text;
  for (const auto& a : driver_arrays(request))
    text += "  " + std::string(a.rows ? "SixRows<S> " : "const S* ") + a.name + ";  // " + a.doc + "\n";
  return text;
}

// Each array's start in the flat input: `drivers_in + 2 * dof + 12` (its offset summed, not
// spelled term by term: a scene with 10 000 instances would otherwise write a quadratic line).
std::string flat_drivers_init(const symbolic::TraceRequest& request) {
  std::string text;
  std::size_t dof_values = 0, fixed_values = 0;
  for (const auto& a : driver_arrays(request)) {
    std::string at = "drivers_in";
    if (dof_values > 0) at += dof_values == 1 ? " + dof" : " + " + std::to_string(dof_values) + " * dof";
    if (fixed_values > 0) at += " + " + std::to_string(fixed_values);
    text += (text.empty() ? "" : ", ") + (a.rows ? "SixRows<S>{" + at + "}" : at);
    dof_values += a.dof_values;
    fixed_values += a.fixed_values;
  }
  return "{" + text + "}";
}

std::string drivers_view_init(const symbolic::TraceRequest& request) {
  std::string text;
  for (const auto& a : driver_arrays(request))
    text += (text.empty() ? "" : ", ") + (a.rows ? "SixRows<Scalar>{drivers." + a.name + "[0]}" : "drivers." + a.name);
  return "{" + text + "}";
}

std::string unpack_drivers(const symbolic::TraceRequest& request) {
  std::string text = "  [[maybe_unused]] const S* cursor = drivers_in;\n";
  for (const auto& a : driver_arrays(request)) text += "  " + a.loops + " drivers." + a.element + " = *cursor++;\n";
  return text;
}

std::string check_drivers(const symbolic::TraceRequest& request) {
  std::string text = "  S residue{};  // NaN/Inf among the drivers (scene: check_inputs; see outward())\n";
  for (const auto& a : driver_arrays(request))
    text += "  " + unrolled(a.loops) + " residue += drivers." + a.element + " - drivers." + a.element + ";\n";
  return text + "  state.drivers_input_status = Lanes<S>::status_if(residue != 0, status_not_finite);";
}

// The order of solver::FlatLayout's `in` (solver/flat_layout.hpp).
std::string flat_in(const symbolic::TraceRequest& request, std::size_t nc, bool floating_base, std::size_t couplings) {
  std::string text = couplings > 0 ? "q (nq), qd (nv)" : floating_base ? "q (nq), qd (dof)" : "q (dof), qd (dof)";
  for (const auto& name : request.layout.torques) text += ", " + name + " (dof)";
  for (const auto& ext : request.layout.external_forces) text += ", " + ext.name + " (6)";
  if (request.layout.run_time_directions() > 0) text += ", alpha (" + alpha_extent(request.layout) + " x 6)";
  if (nc > 0) text += ", beta (constraints)";
  return text;
}

// The order of solver::FlatLayout's `out`.
std::string flat_out(const solver::SolveOutputs& outputs, std::size_t sets, std::size_t loops, std::size_t couplings) {
  std::string text;
  for (const SolutionArray& a : solution_arrays(outputs, sets, loops, couplings)) text += a.name + " (" + a.extent + "), ";
  return text + "status";
}

std::string pack_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets, std::size_t loops,
                          std::size_t couplings) {
  std::string text = "  S* cursor_out = out;\n";
  for (const SolutionArray& a : solution_arrays(outputs, sets, loops, couplings))
    if (nc > 0 || a.name != "nu") text += "  " + unrolled(a.loop) + " *cursor_out++ = solution." + a.element + ";\n";
  text += "  *cursor_out = Lanes<S>::value(solution.status);";
  return text;
}

std::string check_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets, std::size_t loops,
                           std::size_t couplings) {
  std::string text = "  S residue{};  // NaN/Inf among beta and the results (scene: check_inputs; see outward())\n";
  if (nc > 0) text += "  SWEEPGEN_UNROLLED for (int k = 0; k < constraints; ++k) residue += beta[k] - beta[k];\n";
  for (const SolutionArray& a : solution_arrays(outputs, sets, loops, couplings))
    if (nc > 0 || a.name != "nu") text += "  " + unrolled(a.loop) + " residue += out." + a.element + " - out." + a.element + ";\n";
  text.pop_back();  // the template ends the line
  return text;
}

}  // namespace sweepgen::emit
