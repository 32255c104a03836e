#include "emit/solver_emitter.hpp"

#include <kainjow/mustache.hpp>

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "emit/equations.hpp"
#include "emit/function_plan.hpp"
#include "emit/lane_groups.hpp"
#include "emit/function_writer.hpp"
#include "emit/joint_inertia_note.hpp"
#include "emit/literal.hpp"
#include "emit/names.hpp"
#include "emit/templates.hpp"
#include "model/inert_text.hpp"
#include "model/model_notes.hpp"
#include "symbolic/trace_derivatives.hpp"
#include "solver/constraint_row_steps.hpp"
#include "solver/derivative_seeds.hpp"
#include "solver/flat_layout.hpp"
#include "solver/state_fields.hpp"

namespace sweepgen::emit {
namespace {

using kainjow::mustache::data;
using kainjow::mustache::mustache;

std::string render(const std::string& template_name, const data& values) {
  mustache view(embedded_templates().at(template_name));
  if (!view.is_valid()) throw std::logic_error(template_name + ": " + view.error_message());
  return view.render(values);
}

double epsilon_of(const std::string& scalar) {
  if (scalar == "double") return std::numeric_limits<double>::epsilon();
  if (scalar == "float") return std::numeric_limits<float>::epsilon();
  throw std::logic_error("unknown scalar " + scalar);
}

std::string tag_of(const std::string& scalar) { return scalar == "double" ? "f64" : "f32"; }

// The member types of a struct: the header's (one state), or its twin's in the generated source
// (a Batch of states, templates/lanes.mustache).
struct MemberTypes {
  std::string value, flag, count;
};
const MemberTypes kScalarMembers{"Scalar", "bool", "int"};
const MemberTypes kBatchMembers{"Batch", "Lanes<Batch>::Flag", "Lanes<Batch>::Count"};

// Array declarations "  Scalar name[rows][columns];" for the given fields, in first-seen order;
// in a Solution, flags as bool and counts as one int (names.hpp, Storage).
std::string array_members(const symbolic::Trace& trace, const std::vector<std::size_t>& fields, std::size_t bodies,
                          bool solution, const MemberTypes& types = kScalarMembers) {
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

// One array of the Drivers struct: its declarator, the loop header(s) over its values, the
// element those loops reach and what it holds.
struct DriverArray {
  std::string declarator, loops, element, doc;
};

// The extent of the run-time α: `constraints` when every direction is an input.
std::string alpha_extent(const solver::DriverLayout& layout) {
  const std::size_t inputs = layout.run_time_directions();
  return inputs == layout.constraints ? "constraints" : std::to_string(inputs);
}

std::vector<DriverArray> driver_arrays(const symbolic::TraceRequest& request) {
  std::vector<DriverArray> arrays;
  for (const auto& name : request.layout.torques)
    arrays.push_back({name + "[dof]", "for (int i = 0; i < dof; ++i)", name + "[i]", "feed-forward joint torques"});
  for (const auto& ext : request.layout.external_forces)
    arrays.push_back({ext.name + "[6]", "for (int i = 0; i < 6; ++i)", ext.name + "[i]",
                      "wrench [moment; force] on link " + inert_text(ext.link) + ", in its frame"});
  const solver::DriverLayout& layout = request.layout;
  if (layout.run_time_directions() > 0) {
    const std::string extent = alpha_extent(layout);
    arrays.push_back({"alpha[" + extent + "][6]", "for (int k = 0; k < " + extent + "; ++k)\n    for (int i = 0; i < 6; ++i)",
                      "alpha[k][i]",
                      layout.listed_sets() == 0 ? "constraint directions [moment; force], tip frame, unit norm"
                                          : "run-time constraint directions [moment; force], each in its set's link frame, "
                                            "unit norm (sets: see the file header)"});
  }
  return arrays;
}

std::string drivers_members(const symbolic::TraceRequest& request, const std::string& type) {
  std::string text;
  for (const auto& a : driver_arrays(request)) text += "  " + type + " " + a.declarator + ";  // " + a.doc + "\n";
  return text;
}

std::string unpack_drivers(const symbolic::TraceRequest& request) {
  std::string text = "  [[maybe_unused]] const S* cursor = drivers_in;\n";
  for (const auto& a : driver_arrays(request)) text += "  " + a.loops + " drivers." + a.element + " = *cursor++;\n";
  return text;
}

// decompose(): NaN/Inf among the drivers (scene: check_inputs).
std::string check_drivers(const symbolic::TraceRequest& request) {
  std::string text = "  S residue{};  // NaN/Inf among the drivers (scene: check_inputs; see outward())\n";
  for (const auto& a : driver_arrays(request))
    text += "  " + a.loops + " residue += drivers." + a.element + " - drivers." + a.element + ";\n";
  return text + "  state.drivers_input_status = Lanes<S>::status_if(residue != 0, status_not_finite);";
}

// The order of solver::FlatLayout's `in` (solver/flat_layout.hpp).
std::string flat_in(const symbolic::TraceRequest& request, std::size_t nc, bool floating_base) {
  std::string text = floating_base ? "q (nq), qd (dof)" : "q (dof), qd (dof)";
  for (const auto& name : request.layout.torques) text += ", " + name + " (dof)";
  for (const auto& ext : request.layout.external_forces) text += ", " + ext.name + " (6)";
  if (request.layout.run_time_directions() > 0) text += ", alpha (" + alpha_extent(request.layout) + " x 6)";
  if (nc > 0) text += ", beta (constraints)";
  return text;
}

// The Solution arrays the solves return (scene key outputs), in the order of solver::FlatLayout's
// `out` (solver/flat_layout.hpp), with their extents and loop headers (ν without constraints:
// named, with no entries).
struct SolutionArray {
  std::string name, extent, element, loop;
};
std::vector<SolutionArray> solution_arrays(const solver::SolveOutputs& outputs, std::size_t sets) {
  std::vector<SolutionArray> arrays;
  const std::string joints = "for (int i = 0; i < dof; ++i)";
  for (const char* name : {"qdd", "tau_cmd", "tau_ctrl"})
    if (outputs.lists(name)) arrays.push_back({name, "dof", name + std::string("[i]"), joints});
  if (outputs.nu) arrays.push_back({"nu", "constraints", "nu[k]", "for (int k = 0; k < constraints; ++k)"});
  if (outputs.tip_acceleration) arrays.push_back({"tip_acceleration", "6", "tip_acceleration[i]", "for (int i = 0; i < 6; ++i)"});
  if (sets > 0 && outputs.set_acceleration) {
    const std::string n = std::to_string(6 * sets);
    arrays.push_back({"set_acceleration", "6 per constraint set", "set_acceleration[i]", "for (int i = 0; i < " + n + "; ++i)"});
  }
  return arrays;
}

// The order of solver::FlatLayout's `out`.
std::string flat_out(const solver::SolveOutputs& outputs, std::size_t sets) {
  std::string text;
  for (const SolutionArray& a : solution_arrays(outputs, sets)) text += a.name + " (" + a.extent + "), ";
  return text + "status";
}

std::string pack_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets) {
  std::string text = "  S* cursor_out = out;\n";
  for (const SolutionArray& a : solution_arrays(outputs, sets))
    if (nc > 0 || a.name != "nu") text += "  " + a.loop + " *cursor_out++ = solution." + a.element + ";\n";
  text += "  *cursor_out = Lanes<S>::value(solution.status);";
  return text;
}

// solve_<policy>(): NaN/Inf among the setpoints and the results (scene: check_inputs).
std::string check_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets) {
  std::string text = "  S residue{};  // NaN/Inf among beta and the results (scene: check_inputs; see outward())\n";
  if (nc > 0) text += "  for (int k = 0; k < constraints; ++k) residue += beta[k] - beta[k];\n";
  for (const SolutionArray& a : solution_arrays(outputs, sets))
    if (nc > 0 || a.name != "nu") text += "  " + a.loop + " residue += out." + a.element + " - out." + a.element + ";\n";
  text.pop_back();  // the template ends the line
  return text;
}

// One line on how ν is solved (scene keys constraint_factorisation and pivot_tolerance).
std::string factorisation_note(const solver::SolverOptions& options, std::size_t nc) {
  if (nc == 0) return "";
  const std::string tolerance =
      options.pivot_tolerance > 0 ? literal(options.pivot_tolerance, "double") : std::string("1000 epsilon of the scalar");
  return options.constraint_factorisation == solver::ConstraintFactorisation::damped
             ? "E^A_cstr,0: equilibrated, damped by " + tolerance + " (damped least squares; scene: constraint_factorisation)."
             : "E^A_cstr,0: equilibrated; LDL^T in the natural order where the diagonal of the inverse it\n"
               "// gives shows that the pivoted order would keep every direction (C4), else pivoted LDL^T (C2), relative\n"
               "// pivot tolerance " +
                   tolerance + " (scene: constraint_factorisation).";
}

// The type of the groups of lanes (lane_groups.hpp), one lane per constraint direction, by value
// type S: for the scalar, GCC's and clang's vector extension on the host (an SSE2 register, or half
// an AVX one; the same rounding per lane as the scalar code); else (a Batch of states, a GPU,
// SWEEPGEN_SCALAR_LANES) an array with the same operators. A function that computes in lanes names
// it Lanes2 (lanes_alias).
std::string lane_type() {
  const std::string n = std::to_string(LaneGroups::kWidth), loop = "for (int l = 0; l < " + n + "; ++l) ";
  std::string text =
      "\n// Two lanes, two constraint directions of a set (their expressions are alike: computed\n"
      "// together, as in sweepgen's emit/lane_groups.hpp); a set of odd count repeats a lane.\n"
      "template <class S>\nstruct LaneArray {\n  S lane[" + n + "];\n"
      "  SWEEPGEN_HD S operator[](int l) const { return lane[l]; }\n"
      "  friend SWEEPGEN_HD LaneArray operator-(LaneArray a) { " + loop + "a.lane[l] = -a.lane[l]; return a; }\n";
  for (const char* op : {"+", "-", "*", "/"}) {
    const std::string o = op;
    text += "  friend SWEEPGEN_HD LaneArray operator" + o + "(LaneArray a, LaneArray b) { " + loop + "a.lane[l] = a.lane[l] " + o +
            " b.lane[l]; return a; }\n" + "  template <class T>\n  friend SWEEPGEN_HD LaneArray operator" + o +
            "(T s, LaneArray b) { " + loop + "b.lane[l] = s " + o + " b.lane[l]; return b; }\n" +
            "  template <class T>\n  friend SWEEPGEN_HD LaneArray operator" + o + "(LaneArray a, T s) { " + loop +
            "a.lane[l] = a.lane[l] " + o + " s; return a; }\n";
  }
  return text + "};\ntemplate <class S>\nstruct LanesOf {\n  using type = LaneArray<S>;\n};\n"
                "#if defined(SWEEPGEN_BATCH_BYTES)\ntypedef Scalar LaneVector __attribute__((vector_size(" + n +
                " * sizeof(Scalar))));\ntemplate <>\nstruct LanesOf<Scalar> {\n  using type = LaneVector;\n};\n#endif\n";
}

// The first line of a function that computes in lanes: their type for its value type S.
std::string lanes_alias(const FunctionText& text) {
  return text.vector_expressions > 0 ? "  using Lanes" + std::to_string(LaneGroups::kWidth) + " = typename LanesOf<S>::type;\n" : "";
}

// One line on the lanes the code computes in (run-time directions of a set, columns).
std::string lanes_note(std::size_t vector_expressions) {
  return "Lanes: the columns of each set's run-time directions computed two directions at a time (Lanes2; " +
         std::to_string(vector_expressions) + " vector expressions per scalar type).";
}

constexpr std::size_t kFusedOperations = 12000;

// A formulation's operations on the usual path, every function and policy, and how many of them
// its groups of lanes save (lane_groups.hpp).
struct PlannedCost {
  std::size_t operations = 0;
  std::size_t saved_by_lanes = 0;
};

// The cost `constraint_rows: auto` compares: a formulation's operations less what its lanes
// save, the columns' (I2) weighted by 21/20 where they are computed in scalars and carry more
// than two directions. Each such column is a 6-vector live through every body's step; past two
// (12 values) they no longer fit the 16 vector registers of x86-64 and spill, which an operation
// count does not see (bench/code_stats.sh: 3 033 spills with columns against 2 599 with rows on
// panda_nc6). On nine scenes measured both ways (bench/README.md, "Constraint columns (I2) or rows (I6)"),
// rows ran fewer instructions wherever the columns led the count by up to 4.3 % with Nc >= 3,
// columns ran fewer where they led by 6.7 % (panda_nc3) or carried two directions (planar_nc2,
// 1.6 %); 5 % separates them. Run-time directions put the columns in lanes, two per register on
// the baseline, and the weight does not apply (bench/README.md, "Two lanes over the constraint columns").
double rows_cost(solver::ConstraintRows rows, const PlannedCost& cost, std::size_t directions) {
  constexpr std::size_t kColumnsInRegisters = 2;
  constexpr double kSpillingColumnsWeight = 21.0 / 20.0;
  const bool spilling = rows == solver::ConstraintRows::inward_columns && directions > kColumnsInRegisters &&
                        cost.saved_by_lanes == 0;
  return static_cast<double>(cost.operations - cost.saved_by_lanes) * (spilling ? kSpillingColumnsWeight : 1.0);
}

// (I6) is traced only where its outward steps are at most kRowStepsTraced times the columns'
// (solver/constraint_row_steps.hpp): one step of either costs about the same (a transform and a
// projection of a 6-vector), so far beyond 1 the rows cannot win, and their steps grow with the
// square of a chain's length, the columns' with its length (a 1 000-joint chain with a 6-D set at
// its tip: 500 500 against 6 000). The Panda with one direction at its hand traces both at 4
// (28 steps against 7); 8 leaves room above every such arm.
constexpr std::size_t kRowStepsTraced = 8;

// One line on how the rows r_i = S_i^T F^A_cstr,i are formed, with both formulations' counts
// (`steps`: where the rows were not traced, why).
std::string rows_note(solver::ConstraintRows chosen, const std::map<solver::ConstraintRows, PlannedCost>& counted,
                      bool requested, bool exposed, std::size_t directions, const solver::ConstraintRowSteps* steps) {
  const auto count = [&](solver::ConstraintRows rows) {
    const auto found = counted.find(rows);
    if (found == counted.end()) return std::string();
    const PlannedCost& c = found->second;
    return " (" + std::to_string(c.operations) + " operations" +
           (c.saved_by_lanes ? ", " + std::to_string(c.operations - c.saved_by_lanes) + " counting two lanes as one" : "") +
           ")";
  };
  const std::string columns = "columns F^A_cstr,i inward (I2)" + count(solver::ConstraintRows::inward_columns);
  const std::string rows = "rows r_i outward (I6)" + count(solver::ConstraintRows::outward_rows);
  const bool outward = chosen == solver::ConstraintRows::outward_rows;
  const auto columns_cost = counted.find(solver::ConstraintRows::inward_columns);
  const bool weighted = columns_cost != counted.end() &&
                        rows_cost(solver::ConstraintRows::inward_columns, columns_cost->second, directions) >
                            static_cast<double>(columns_cost->second.operations);
  const std::string why = requested ? " (scene: constraint_rows)"
                          : exposed ? " (scene: expose: all lists the columns)"
                          : steps   ? ", not the rows r_i outward (I6), not traced: their " +
                                        std::to_string(steps->outward_rows) + " outward steps are more than " +
                                        std::to_string(kRowStepsTraced) + " times the columns' " +
                                        std::to_string(steps->inward_columns) + " (scene: constraint_rows: auto)"
                                    : ", not the " + (outward ? columns : rows) + " (scene: constraint_rows: auto" +
                                          (weighted ? ", the columns' count weighted by 21/20" : "") + ")";
  return "Constraint rows r_i = S_i^T F^A_cstr,i: " + (outward ? rows : columns) + why + ".";
}

// Operations of one planned trace on its usual path, and what its lanes save.
PlannedCost planned_cost(const symbolic::Trace& trace, const Plan& plan) {
  OpCount ops;
  PlannedCost cost;
  for (const auto& f : plan.functions) {
    for (NodeId id : f.computed)
      if (plan.guard[id] == kAlways || plan.guard[id] % 2 == 0) ops.count(trace.graph.node(id).op);
    cost.saved_by_lanes += find_lane_groups(trace, f).operations_saved();
  }
  cost.operations = ops.total();
  return cost;
}

const char* policy_doc(const std::string& group) {
  if (group == "original") return "Alg. 3, the original composition of every driver.";
  if (group == "prioritize_external") return "Alg. 4: the constraint does not react to external forces.";
  if (group == "saturate") return "Eq. 1: tau_ctrl clamped to the effort limits; tau_cmd = RNEA(qdd).";
  return "Exact saturation: tau_cmd clamped to the effort limits, forward dynamics with it.";
}

// ---- Derivatives (scene key derivatives; docs/derivation.md, D1–D8) ----

// The arrays of a derivative function's Derivatives, in the order of its flat output: the values,
// then the Jacobians the scene asks for (scene key derivatives).
std::vector<std::pair<std::string, std::size_t>> derivative_arrays(std::size_t n, std::size_t nc,
                                                                   const solver::DerivativeOutputs& outputs) {
  const std::size_t columns = solver::DerivativeColumns{n, nc}.count();
  std::vector<std::pair<std::string, std::size_t>> arrays = {
      {"qdd", n}, {"nu", nc}, {"tau_cmd", n}, {"d_qdd", outputs.qdd ? n * columns : 0},
      {"d_nu", outputs.nu ? nc * columns : 0}, {"d_tau_cmd", outputs.tau_cmd ? n * columns : 0}};
  arrays.erase(std::remove_if(arrays.begin(), arrays.end(), [](const auto& a) { return a.second == 0; }), arrays.end());
  return arrays;
}

std::string derivative_flat_out(std::size_t n, std::size_t nc, const solver::DerivativeOutputs& outputs) {
  std::string text;
  for (const auto& [name, size] : derivative_arrays(n, nc, outputs))
    text += name + " (" + (name.rfind("d_", 0) == 0 ? std::string(name == "d_nu" ? "constraints" : "dof") + " x derivative_columns"
                                                     : std::string(name == "nu" ? "constraints" : "dof")) + "), ";
  return text + "status";
}

std::string pack_derivatives(std::size_t n, std::size_t nc, const solver::DerivativeOutputs& outputs) {
  std::string text = "  S* cursor_out = out;\n";
  for (const auto& [name, size] : derivative_arrays(n, nc, outputs))
    text += "  for (int i = 0; i < " + std::to_string(size) + "; ++i) *cursor_out++ = derivatives." + name + "[i];\n";
  return text + "  *cursor_out = Lanes<S>::value(derivatives.status);";
}

// The Jacobians the derivative functions return and those left out (scene key derivatives), one
// line for `sweepgen info`.
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

// NaN/Inf among the results (scene: check_inputs): one in an input the results depend on reaches them.
std::string check_derivatives(std::size_t n, std::size_t nc, const solver::DerivativeOutputs& outputs) {
  std::string text = "  S residue{};  // NaN/Inf among the results (scene: check_inputs; see outward())\n";
  for (const auto& [name, size] : derivative_arrays(n, nc, outputs)) text += "  for (const S& x : out." + name + ") residue += x - x;\n";
  return text + "  status |= Lanes<S>::status_if(residue != 0, status_not_finite);";
}

}  // namespace

std::string file_stem(const std::string& solver_namespace) {
  std::string stem;
  for (std::size_t i = 0; i < solver_namespace.size(); ++i) {
    if (solver_namespace.compare(i, 2, "::") == 0) {
      stem += '_';
      ++i;
    } else {
      stem += solver_namespace[i];
    }
  }
  return stem;
}

EmittedSolver emit_solver(const model::Chain& chain, const EmitRequest& request) {
  EmittedSolver result;
  const std::size_t n = chain.dof();
  const std::size_t nc = request.trace.layout.constraints, sets = request.trace.layout.listed_sets();
  const std::string stem = file_stem(request.solver_namespace);

  data op_lines{data::type::list};
  data variants{data::type::list};
  std::string rows_line, lanes_line;
  for (const std::string& scalar : request.scalars) {
    symbolic::TraceRequest trace_request = request.trace;
    trace_request.epsilon = epsilon_of(scalar);
    // (I2) or (I6): as the scene asks, else the one of lower rows_cost (ties: the columns).
    std::vector<solver::ConstraintRows> candidates{solver::ConstraintRows::inward_columns};
    const solver::ConstraintRowSteps steps = solver::constraint_row_steps(chain, request.trace.layout);
    const bool rows_too_long = steps.outward_rows > kRowStepsTraced * steps.inward_columns;
    if (request.constraint_rows) candidates = {*request.constraint_rows};
    else if (request.trace.layout.constraints > 0 && !request.expose_all && !rows_too_long)
      candidates.push_back(solver::ConstraintRows::outward_rows);
    std::optional<symbolic::Trace> best_trace;
    std::optional<Plan> best_plan;
    std::map<solver::ConstraintRows, PlannedCost> counted;
    for (const solver::ConstraintRows rows : candidates) {
      trace_request.options.constraint_rows = rows;
      symbolic::Trace candidate = symbolic::trace_solver(chain, trace_request);
      Plan candidate_plan = make_plan(candidate, request.expose_all);
      counted[rows] = planned_cost(candidate, candidate_plan);
      if (!best_plan || rows_cost(rows, counted[rows], nc) <
                            rows_cost(best_trace->constraint_rows, counted[best_trace->constraint_rows], nc)) {
        best_trace = std::move(candidate);
        best_plan = std::move(candidate_plan);
      }
    }
    const symbolic::Trace& trace = *best_trace;
    const Plan& plan = *best_plan;
    trace_request.options.constraint_rows = trace.constraint_rows;  // for the derivatives' trace
    result.constraint_rows = trace.constraint_rows;
    if (rows_line.empty() && request.trace.layout.constraints > 0)
      rows_line = rows_note(trace.constraint_rows, candidates.size() > 1 ? counted : decltype(counted){},
                            request.constraint_rows.has_value(), request.expose_all, nc, rows_too_long ? &steps : nullptr);

    data variant;
    variant.set("scalar", scalar);
    variant.set("outward_rows", trace.constraint_rows == solver::ConstraintRows::outward_rows ? "true" : "false");
    variant.set("tag", tag_of(scalar));
    variant.set("drivers_members", drivers_members(request.trace, kScalarMembers.value));
    variant.set("batch_drivers_members", drivers_members(request.trace, kBatchMembers.value));

    for (const MemberTypes* types : {&kScalarMembers, &kBatchMembers}) {
      std::string state = array_members(trace, plan.state_fields, n + 1, false, *types);
      for (const auto& [node, name] : plan.carried_name) state += "  " + types->value + " " + name + ";\n";
      variant.set(types == &kScalarMembers ? "state_members" : "batch_state_members", state);
    }

    std::vector<std::size_t> solution_fields;
    std::set<std::string> seen;
    for (const auto& f : plan.functions)
      for (std::size_t i : f.fields)
        if (!is_state_field(trace.fields[i])) solution_fields.push_back(i);
    variant.set("solution_members", array_members(trace, solution_fields, n + 1, true));
    variant.set("batch_solution_members", array_members(trace, solution_fields, n + 1, true, kBatchMembers));

    OpCount shared, shared_worst;
    std::size_t vector_expressions = 0;
    std::vector<std::string> worst_lines;  // where a path condition (C4) makes the worst case differ
    data solves{data::type::list};
    for (const auto& f : plan.functions) {
      const FunctionText text = write_function(trace, plan, f, chain, scalar);
      vector_expressions += text.vector_expressions;
      result.costs.push_back({scalar, f.name, text.ops});
      op_lines.push_back(data("line", tag_of(scalar) + "::" + f.name + ": " + text.ops.summary()));
      if (f.stage < symbolic::stage_solve) {
        shared += text.ops;
        shared_worst += text.worst;
        variant.set(f.name + "_body", lanes_alias(text) + text.body);
        continue;
      }
      OpCount full = shared, full_worst = shared_worst;
      full += text.ops;
      full_worst += text.worst;
      result.costs.push_back({scalar, "full " + f.name, full});
      op_lines.push_back(data("line", tag_of(scalar) + ": outward + decompose + " + f.name + ": " + full.summary()));
      if (full_worst.total() != full.total())
        worst_lines.push_back(tag_of(scalar) + ", pivoted path: outward + decompose + " + f.name + ": " +
                              full_worst.summary());
      data solve;
      solve.set("name", f.name);
      solve.set("policy", f.group);
      solve.set("doc", policy_doc(f.group));
      solve.set("body", lanes_alias(text) + text.body);
      // Only the saturating policies set a flag of `saturated` (the others write false).
      solve.set("saturates", f.group == solver::name(solver::Policy::saturate) ||
                                 f.group == solver::name(solver::Policy::saturate_exact));
      solve.set("pack_solution", pack_solution(request.trace.outputs, nc, sets));
      solves.push_back(solve);
    }
    for (const std::string& line : worst_lines) op_lines.push_back(data("line", line));
    variant.set("solves", solves);
    if (request.derivatives) {
      const symbolic::Trace derivative_trace = symbolic::trace_derivatives(chain, trace_request, request.derivative_outputs);
      const Plan derivative_plan = make_single_pass_plan(derivative_trace, "derivatives_");
      variant.set("derivatives_members",
                  array_members(derivative_trace, derivative_plan.functions.front().fields, n + 1, true));
      variant.set("batch_derivatives_members",
                  array_members(derivative_trace, derivative_plan.functions.front().fields, n + 1, true, kBatchMembers));
      data functions{data::type::list};
      for (const auto& f : derivative_plan.functions) {
        const FunctionText text = write_function(derivative_trace, derivative_plan, f, chain, scalar);
        vector_expressions += text.vector_expressions;
        result.costs.push_back({scalar, f.name, text.ops});
        op_lines.push_back(data("line", tag_of(scalar) + "::" + f.name + ": " + text.ops.summary()));
        data function;
        function.set("name", f.name);
        function.set("policy", f.group);
        function.set("doc", policy_doc(f.group));
        function.set("body", lanes_alias(text) + text.body);
        function.set("check", check_derivatives(n, nc, request.derivative_outputs));
        function.set("pack", pack_derivatives(n, nc, request.derivative_outputs));
        functions.push_back(function);
      }
      variant.set("derivative_functions", functions);
    }
    variant.set("lane_types", vector_expressions > 0 ? lane_type() : "");
    if (lanes_line.empty() && vector_expressions > 0) lanes_line = lanes_note(vector_expressions);
    variant.set("flat_in", flat_in(request.trace, nc, chain.floating_base));
    variant.set("flat_out", flat_out(request.trace.outputs, sets));
    const auto flat = solver::FlatLayout::of(request.trace.layout, n, chain.floating_base, request.trace.outputs);
    variant.set("flat_in_size", std::to_string(flat.in_size()));
    variant.set("flat_out_size", std::to_string(flat.out_size()));
    variant.set("unpack_drivers", unpack_drivers(request.trace));
    variant.set("check_drivers", check_drivers(request.trace));
    variant.set("check_solution", check_solution(request.trace.outputs, nc, sets));
    variant.set("state_note", request.expose_all ? ", and every intermediate of the sweeps (expose: all)"
                                                 : " (expose: outputs; carried values only)");
    variants.push_back(variant);
  }

  // Fusing the flat solves (templates/solver.cpp.mustache) puts one more copy of the whole
  // solve into the file per policy and scalar; they are fused while the file stays within
  // kFusedOperations operations (measured: every bundled scene within it compiles in <= 5 s at
  // -O2 on a 2-core VM, bench/README.md, "The fused flat solve").
  std::size_t file_operations = 0, fused_operations = 0;
  for (const FunctionCost& cost : result.costs) {
    const bool full = cost.function.rfind("full ", 0) == 0;
    (full ? fused_operations : file_operations) += cost.ops.total();
  }
  const bool fused = file_operations + fused_operations <= kFusedOperations;

  data values;
  values.set("fused", fused);
  values.set("lanes_runtime", embedded_templates().at("lanes.mustache"));
  values.set("fused_note", std::to_string(file_operations + fused_operations) + " operations in this file, at most " +
                               std::to_string(kFusedOperations) + " fused");
  values.set("provenance", request.provenance);
  values.set("robot", inert_text(chain.source.substr(chain.source.find_last_of('/') + 1)));
  values.set("root", inert_text(chain.root_link));
  std::string tips = inert_text(chain.tip_link);
  for (const std::string& tip : chain.branch_tips) tips += ", " + inert_text(tip);
  values.set("tip", chain.branch_tips.empty() ? tips
                                             : tips + " (a tree; tip_acceleration is " + inert_text(chain.tip_link) + "'s)");
  values.set("dof", std::to_string(n));
  // A floating base (F5): q = [world_R_base (9); the joints' positions], qd etc. lead with the
  // base's twist.
  const bool floating = chain.floating_base;
  values.set("floating_base_note",
             floating ? "\n// Floating base (docs/derivation.md, F5): " + inert_text(chain.root_link) +
                            " moves freely. q = [world_R_base (9 values,\n"
                            "// row-major: base coordinates -> world; it turns gravity into the base frame, the base's\n"
                            "// position does not enter), then the nq - 9 joints' positions]. qd, qdd, tau_ff, tau_cmd and\n"
                            "// tau_ctrl have dof entries, the first six the base's: qd[0..5] its twist [omega; v] in its own\n"
                            "// frame, qdd[0..5] its spatial acceleration (d/dt of those six numbers, gravity not included;\n"
                            "// the classical acceleration of its origin is R (qdd[3..5] + omega x v)), tau[0..5] a wrench\n"
                            "// [moment; force] on it about its origin, in its frame."
                      : "");
  values.set("nq_line", "\nconstexpr int nq = " + std::to_string(floating ? n + 3 : n) +
                            (floating ? ";  // values of q: world_R_base (9, row-major), then the joints'"
                                      : ";  // values of q (= dof: a fixed base)"));
  values.set("q_pre", floating ? "nq and dof values" : "dof values each");
  values.set("q_size", floating ? "nq" : "dof");
  values.set("drivers_offset", floating ? "nq + dof" : "2 * dof");
  data lumping{data::type::list};
  for (const std::string& line : model::lumping_summary(chain)) lumping.push_back(data("line", line));
  values.set("lumping", lumping);
  data notes{data::type::list};
  const std::vector<std::string> note_lines = model::model_notes(chain);
  for (const std::string& line : note_lines) notes.push_back(data("line", line));
  values.set("has_model_notes", !note_lines.empty());
  values.set("model_notes", notes);
  values.set("constraints", std::to_string(nc));
  const solver::DriverLayout& layout = request.trace.layout;
  const std::size_t run_time = layout.run_time_directions();
  values.set("directions_note", run_time == nc ? "" : run_time == 0 ? ", fixed" : ", " + std::to_string(nc - run_time) + " fixed");
  values.set("alpha_note", run_time > 0 ? ", alpha" : "");
  std::string sets_note =
      sets > 0 ? "\n// Constraint sets: each set's alpha and set_acceleration are in its own link's frame (not the tip's):" : "";
  for (const std::string& line : constraint_set_summary(layout)) sets_note += "\n//   " + line;
  values.set("constraint_sets_note", sets_note);
  values.set("namespace", request.solver_namespace);
  values.set("has_constraints", nc > 0);
  values.set("factorisation_note", factorisation_note(request.trace.options, nc));
  values.set("rows_note", rows_line.empty() ? "" : "\n// " + rows_line);
  if (!rows_line.empty()) result.choices.push_back(rows_line);
  values.set("lanes_note", lanes_line.empty() ? "" : "\n// " + lanes_line);
  if (!lanes_line.empty()) result.choices.push_back(lanes_line);
  std::vector<double> epsilons;
  for (const std::string& scalar : request.scalars) epsilons.push_back(epsilon_of(scalar));
  const std::string joint_line =
      joint_inertia_note(chain, request.trace.layout, request.trace.options, request.scalars, epsilons);
  values.set("joint_inertia_note", joint_line);
  result.choices.push_back(joint_line);
  result.choices.push_back(fused ? "solve_<policy>_flat: one function each (outward, decompose and the solve inlined)"
                                 : "solve_<policy>_flat: calls outward, decompose and the solve (" +
                                       std::to_string(file_operations + fused_operations) + " operations fused would exceed " +
                                       std::to_string(kFusedOperations) + ")");
  if (nc > 0) {
    std::string factorisation = factorisation_note(request.trace.options, nc);
    for (std::size_t at; (at = factorisation.find("\n// ")) != std::string::npos;) factorisation.replace(at, 4, " ");
    result.choices.push_back(factorisation);
  }
  if (request.derivatives) result.choices.push_back(derivatives_line(request.derivative_outputs, nc));
  values.set("rank_deficient_doc", request.trace.options.constraint_factorisation == solver::ConstraintFactorisation::damped
                                       ? "a damped pivot of E^A_cstr,0 was <= 2 tol: the damping\n"
                                         "                                               // changed some multipliers by ~2x or more"
                                       : "a pivot of E^A_cstr,0 fell below tolerance: some\n"
                                         "                                               // constraint directions were not enforced");
  values.set("has_derivatives", request.derivatives);
  values.set("derivative_columns", std::to_string(solver::DerivativeColumns{n, nc}.count()));
  values.set("derivative_flat_out", derivative_flat_out(n, nc, request.derivative_outputs));
  values.set("derivative_flat_out_size",
             std::to_string(request.derivative_outputs.flat_out_size(solver::DerivativeColumns{n, nc})));
  values.set("derivative_of_qdd", request.derivative_outputs.qdd ? "true" : "false");
  values.set("derivative_of_nu", request.derivative_outputs.nu ? "true" : "false");
  values.set("derivative_of_tau_cmd", request.derivative_outputs.tau_cmd ? "true" : "false");
  values.set("check_inputs", request.check_inputs);
  values.set("check_inputs_value", request.check_inputs ? "true" : "false");
  values.set("returns_every_output", request.trace.outputs.all() ? "true" : "false");
  values.set("op_counts", op_lines);
  values.set("variants", variants);
  values.set("header_name", stem + ".hpp");
  values.set("source_name", stem + ".cpp");
  values.set("target", stem);
  result.files.push_back({stem + ".hpp", render("solver.hpp.mustache", values)});
  result.files.push_back({stem + ".cpp", render("solver.cpp.mustache", values)});
  result.files.push_back({stem + ".cu", render("solver.cu.mustache", values)});
  result.files.push_back({stem + ".cmake", render("solver.cmake.mustache", values)});
  return result;
}

}  // namespace sweepgen::emit
