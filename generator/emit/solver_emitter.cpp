#include "emit/solver_emitter.hpp"

#include <kainjow/mustache.hpp>

#include <limits>
#include <sstream>
#include <stdexcept>

#include "emit/constant_check.hpp"
#include "emit/constraint_rows_choice.hpp"
#include "emit/derivative_text.hpp"
#include "emit/function_plan.hpp"
#include "emit/function_writer.hpp"
#include "emit/joint_inertia_note.hpp"
#include "emit/literal.hpp"
#include "emit/lane_groups.hpp"
#include "emit/names.hpp"
#include "emit/struct_text.hpp"
#include "emit/templates.hpp"
#include "io/output_files.hpp"
#include "model/inert_text.hpp"
#include "model/model_notes.hpp"
#include "symbolic/trace_derivatives.hpp"
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

const char* policy_doc(const std::string& group) {
  if (group == "original") return "Alg. 3, the original composition of every driver.";
  if (group == "prioritize_external") return "Alg. 4: the constraint does not react to external forces.";
  if (group == "saturate") return "Eq. 1: tau_ctrl clamped to the effort limits; tau_cmd = RNEA(qdd).";
  return "Exact saturation: tau_cmd clamped to the effort limits, forward dynamics with it.";
}

// What the writers of one scalar's functions add up across the file: the operation counts (the
// header's lines and `sweepgen info`'s), and the first scalar's notes on its choices.
struct FileTally {
  data op_lines{data::type::list};
  std::string rows_line, lanes_line;
};

// The functions of one plan (the stages and solves, or the derivative functions) written for
// `scalar`, in the plan's order; their vector expressions added to `vector_expressions`.
std::vector<std::pair<const FunctionPlan*, FunctionText>> write_functions(const symbolic::Trace& trace,
                                                                             const Plan& plan,
                                                                             const model::Chain& chain,
                                                                             const std::string& scalar,
                                                                             std::size_t& vector_expressions) {
  std::vector<std::pair<const FunctionPlan*, FunctionText>> written;
  for (const auto& f : plan.functions) {
    FunctionText text = write_function(trace, plan, f, chain, scalar);
    vector_expressions += text.vector_expressions;
    written.emplace_back(&f, std::move(text));
  }
  return written;
}

// A function's operations, in `result` and among the header's lines.
void count_function(const std::string& scalar, const std::string& name, const OpCount& ops, EmittedSolver& result,
                    FileTally& tally) {
  result.costs.push_back({scalar, name, ops});
  tally.op_lines.push_back(data("line", tag_of(scalar) + "::" + name + ": " + ops.summary()));
}

// One solve per policy of the scalar's plan: its template values; the full solve's operations
// (outward + decompose + the solve), on the usual path and where (C4)'s pivoted path differs.
data solve_values(const std::vector<std::pair<const FunctionPlan*, FunctionText>>& written,
                  const EmitRequest& request, const std::string& scalar, data& variant, EmittedSolver& result,
                  FileTally& tally, std::size_t couplings) {
  const std::size_t nc = request.trace.layout.constraints, sets = request.trace.layout.listed_sets(),
                    loops = request.trace.layout.loop_sets();
  OpCount shared, shared_worst;
  std::vector<std::string> worst_lines;
  data solves{data::type::list};
  for (const auto& [f, text] : written) {
    count_function(scalar, f->name, text.ops, result, tally);
    if (f->stage < symbolic::stage_solve) {
      shared += text.ops;
      shared_worst += text.worst;
      variant.set(f->name + "_body", lanes_alias(text) + text.body);
      continue;
    }
    OpCount full = shared, full_worst = shared_worst;
    full += text.ops;
    full_worst += text.worst;
    result.costs.push_back({scalar, "full " + f->name, full});
    tally.op_lines.push_back(data("line", tag_of(scalar) + ": outward + decompose + " + f->name + ": " + full.summary()));
    if (full_worst.total() != full.total())
      worst_lines.push_back(tag_of(scalar) + ", pivoted path: outward + decompose + " + f->name + ": " + full_worst.summary());
    data solve;
    solve.set("name", f->name);
    solve.set("policy", f->group);
    solve.set("doc", policy_doc(f->group));
    solve.set("body", lanes_alias(text) + text.body);
    // Only the saturating policies set a flag of `saturated` (the others write false).
    solve.set("saturates", f->group == solver::name(solver::Policy::saturate) ||
                               f->group == solver::name(solver::Policy::saturate_exact));
    solve.set("pack_solution", pack_solution(request.trace.outputs, nc, sets, loops, couplings));
    solves.push_back(solve);
  }
  for (const std::string& line : worst_lines) tally.op_lines.push_back(data("line", line));
  return solves;
}

// The derivative functions (scene key derivatives, D1–D8), traced with the chosen rows: their
// Derivatives members are set on `variant`, the functions returned.
data derivative_values(const model::Chain& chain, const EmitRequest& request, const symbolic::TraceRequest& trace_request,
                       const std::string& scalar, data& variant, EmittedSolver& result, FileTally& tally,
                       std::size_t& vector_expressions) {
  const std::size_t n = chain.dof();
  const auto columns = solver::DerivativeColumns::of(n, request.trace.layout.constraints, chain.couplings);
  const symbolic::Trace trace = symbolic::trace_derivatives(chain, trace_request, request.derivative_outputs);
  const Plan plan = make_single_pass_plan(trace, "derivatives_");
  check_constants_finite(trace, plan, chain, trace_request.options, scalar);
  variant.set("derivatives_members", array_members(trace, plan.functions.front().fields, n + 1, true));
  variant.set("batch_derivatives_members", array_members(trace, plan.functions.front().fields, n + 1, true, kBatchMembers));
  data functions{data::type::list};
  for (const auto& [f, text] : write_functions(trace, plan, chain, scalar, vector_expressions)) {
    count_function(scalar, f->name, text.ops, result, tally);
    data function;
    function.set("name", f->name);
    function.set("policy", f->group);
    function.set("doc", policy_doc(f->group));
    function.set("body", lanes_alias(text) + text.body);
    function.set("check", check_derivatives(columns, request.derivative_outputs));
    function.set("pack", pack_derivatives(columns, request.derivative_outputs));
    functions.push_back(function);
  }
  return functions;
}

// One scalar's part of the templates' values (a `variants` entry): its structs' members for one
// state and for a Batch, its stages, solves and derivative functions, its flat layout.
data variant_values(const model::Chain& chain, const EmitRequest& request, const std::string& scalar,
                    EmittedSolver& result, FileTally& tally) {
  const std::size_t n = chain.dof(), nc = request.trace.layout.constraints, sets = request.trace.layout.listed_sets(),
                    loops = request.trace.layout.loop_sets(), couplings = chain.couplings.size();
  symbolic::TraceRequest trace_request = request.trace;
  trace_request.epsilon = epsilon_of(scalar);
  const ChosenRows chosen = choose_constraint_rows(chain, request, trace_request);
  const symbolic::Trace& trace = chosen.trace;
  const Plan& plan = chosen.plan;
  trace_request.options.constraint_rows = trace.constraint_rows;  // for the derivatives' trace
  result.constraint_rows = trace.constraint_rows;
  if (tally.rows_line.empty()) tally.rows_line = chosen.note;

  data variant;
  variant.set("scalar", scalar);
  variant.set("outward_rows", trace.constraint_rows == solver::ConstraintRows::outward_rows ? "true" : "false");
  variant.set("tag", tag_of(scalar));
  variant.set("drivers_members", drivers_members(request.trace, kScalarMembers.value));
  for (const MemberTypes* types : {&kScalarMembers, &kBatchMembers}) {
    std::string state = array_members(trace, plan.state_fields, n + 1, false, *types);
    for (const auto& [node, name] : plan.carried_name) state += "  " + types->value + " " + name + ";\n";
    variant.set(types == &kScalarMembers ? "state_members" : "batch_state_members", state);
  }
  std::vector<std::size_t> solution_fields;
  for (const auto& f : plan.functions)
    for (std::size_t i : f.fields)
      if (!is_state_field(trace.fields[i])) solution_fields.push_back(i);
  variant.set("solution_members", array_members(trace, solution_fields, n + 1, true));
  variant.set("batch_solution_members", array_members(trace, solution_fields, n + 1, true, kBatchMembers));

  check_constants_finite(trace, plan, chain, trace_request.options, scalar);
  std::size_t vector_expressions = 0;
  const auto written = write_functions(trace, plan, chain, scalar, vector_expressions);
  variant.set("solves", solve_values(written, request, scalar, variant, result, tally, couplings));
  if (request.derivatives)
    variant.set("derivative_functions",
                derivative_values(chain, request, trace_request, scalar, variant, result, tally, vector_expressions));
  variant.set("lane_types", vector_expressions > 0 ? lane_type() : "");
  if (tally.lanes_line.empty() && vector_expressions > 0) tally.lanes_line = lanes_note(vector_expressions);
  variant.set("flat_in", flat_in(request.trace, nc, chain.floating_base, couplings));
  variant.set("flat_out", flat_out(request.trace.outputs, sets, loops, couplings));
  const auto flat = solver::FlatLayout::of(request.trace.layout, chain, request.trace.outputs);
  variant.set("flat_in_size", std::to_string(flat.in_size()));
  variant.set("flat_out_size", std::to_string(flat.out_size()));
  variant.set("unpack_drivers", unpack_drivers(request.trace));
  variant.set("drivers_view_init", drivers_view_init(request.trace));
  variant.set("check_drivers", check_drivers(request.trace));
  variant.set("check_solution", check_solution(request.trace.outputs, nc, sets, loops, couplings));
  variant.set("state_note", request.expose_all ? ", and every intermediate of the sweeps (expose: all)"
                                               : " (expose: outputs; carried values only)");
  return variant;
}

// Fusing the flat solves (templates/solver.cpp.mustache) puts one more copy of the whole solve
// into the file per policy and scalar; they are fused while the file stays within
// kFusedOperations operations (measured: every bundled scene within it compiles in <= 5 s at -O2
// on a 2-core VM, bench/README.md, "The fused flat solve").
struct Fusion {
  bool fused = false;
  std::size_t operations = 0;  // the file's, with the fused solves
};
Fusion fusion_of(const std::vector<FunctionCost>& costs) {
  std::size_t file_operations = 0, fused_operations = 0;
  for (const FunctionCost& cost : costs) {
    const bool full = cost.function.rfind("full ", 0) == 0;
    (full ? fused_operations : file_operations) += cost.ops.total();
  }
  return {file_operations + fused_operations <= kFusedOperations, file_operations + fused_operations};
}

// On which joints (J1) stays (joint_inertia_note.hpp), for every emitted scalar.
std::string joint_inertia_line(const model::Chain& chain, const EmitRequest& request) {
  std::vector<double> epsilons;
  for (const std::string& scalar : request.scalars) epsilons.push_back(epsilon_of(scalar));
  return joint_inertia_note(chain, request.trace.layout, request.trace.options, request.scalars, epsilons);
}

// The emitter's choices, one line each (the generated header and `sweepgen info`).
std::vector<std::string> emitter_choices(const EmitRequest& request, const FileTally& tally,
                                         const std::string& joint_line, const Fusion& fusion) {
  const std::size_t nc = request.trace.layout.constraints;
  std::vector<std::string> choices;
  if (!tally.rows_line.empty()) choices.push_back(tally.rows_line);
  if (!tally.lanes_line.empty()) choices.push_back(tally.lanes_line);
  choices.push_back(joint_line);
  choices.push_back(fusion.fused ? "solve_<policy>_flat: one function each (outward, decompose and the solve inlined)"
                                 : "solve_<policy>_flat: calls outward, decompose and the solve (" +
                                       std::to_string(fusion.operations) + " operations fused would exceed " +
                                       std::to_string(kFusedOperations) + ")");
  if (nc > 0) {
    std::string factorisation = factorisation_note(request.trace.options, nc);
    for (std::size_t at; (at = factorisation.find("\n// ")) != std::string::npos;) factorisation.replace(at, 4, " ");
    choices.push_back(factorisation);
  }
  if (request.derivatives) choices.push_back(derivatives_line(request.derivative_outputs, nc));
  return choices;
}

// The file-wide values of the templates: the robot, its model notes, the layout's sizes, the
// emitter's choices as the header states them and the operation counts.
data file_values(const model::Chain& chain, const EmitRequest& request, const FileTally& tally,
                 const std::string& joint_line, const Fusion& fusion) {
  const std::size_t n = chain.dof(), nc = request.trace.layout.constraints, sets = request.trace.layout.listed_sets();
  data values;
  values.set("fused", fusion.fused);
  values.set("lanes_runtime", embedded_templates().at("lanes.mustache"));
  values.set("flat_drivers_members", flat_drivers_members(request.trace));
  values.set("flat_drivers_init", flat_drivers_init(request.trace));
  values.set("fused_note", std::to_string(fusion.operations) + " operations in this file, at most " +
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
  const std::size_t positions = (floating ? n + 3 : n) - chain.couplings.size();
  values.set("nq_line", "\nconstexpr int nq = " + std::to_string(positions) +
                            (floating ? ";  // values of q: world_R_base (9, row-major), then the joints'"
                             : chain.couplings.empty() ? ";  // values of q (= dof: a fixed base)"
                                                        : ";  // values of q: the joints but the coupled ones"));
  // Coupled <mimic> joints (M1): q and qd hold the other joints only.
  const std::size_t couplings = chain.couplings.size();
  values.set("couplings_line",
             couplings == 0 ? "\nconstexpr int nv = dof;  // values of qd (= dof: no coupled <mimic> joints)"
                            : "\nconstexpr int couplings = " + std::to_string(couplings) +
                                  ";  // coupled <mimic> joints (docs/derivation.md, M1): no entry in q, qd\n"
                                  "constexpr int nv = dof - couplings;  // values of qd");
  if (couplings > 0) {
    std::string note = "\n// Coupled <mimic> joints (docs/derivation.md, M1, M2; scene key mimic: coupled): q and qd hold the\n"
                       "// other joints only, in joint order; each coupled joint follows its source exactly,\n"
                       "// q = k q_source + o. qdd, tau_ff, tau_cmd and tau_ctrl cover every joint; coupling_torque[c]\n"
                       "// is coupling c's transmission torque (+lambda on the joint, -k lambda on its source):";
    for (std::size_t c = 0; c < couplings; ++c) {
      const model::JointCoupling& coupling = chain.couplings[c];
      std::ostringstream line;
      line.precision(17);
      line << "\n//   coupling " << c << ": joint " << coupling.joint << " " << inert_text(chain.joints[coupling.joint].name)
           << " = " << coupling.multiplier << " * joint " << coupling.source << " "
           << inert_text(chain.joints[coupling.source].name) << " + " << coupling.offset;
      note += line.str();
    }
    values.set("couplings_note", note);
  } else {
    values.set("couplings_note", "");
  }
  const std::string velocities = couplings > 0 ? "nv" : "dof";
  values.set("q_pre", floating || couplings > 0 ? "nq and " + velocities + " values" : "dof values each");
  values.set("q_size", floating || couplings > 0 ? "nq" : "dof");
  values.set("qd_size", velocities);
  values.set("drivers_offset", floating || couplings > 0 ? "nq + " + velocities : "2 * dof");
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
  values.set("rows_note", tally.rows_line.empty() ? "" : "\n// " + tally.rows_line);
  values.set("lanes_note", tally.lanes_line.empty() ? "" : "\n// " + tally.lanes_line);
  values.set("joint_inertia_note", joint_line);
  values.set("rank_deficient_doc", request.trace.options.constraint_factorisation == solver::ConstraintFactorisation::damped
                                       ? "a damped pivot of E^A_cstr,0 was <= 2 tol: the damping\n"
                                         "                                               // changed some multipliers by ~2x or more"
                                       : "a pivot of E^A_cstr,0 fell below tolerance: some\n"
                                         "                                               // constraint directions were not enforced");
  values.set("has_derivatives", request.derivatives);
  const auto columns = solver::DerivativeColumns::of(n, nc, chain.couplings);
  values.set("derivative_columns", std::to_string(columns.count()));
  values.set("derivative_flat_out", derivative_flat_out(columns, request.derivative_outputs));
  values.set("derivative_flat_out_size", std::to_string(request.derivative_outputs.flat_out_size(columns)));
  values.set("derivative_of_qdd", request.derivative_outputs.qdd ? "true" : "false");
  values.set("derivative_of_nu", request.derivative_outputs.nu ? "true" : "false");
  values.set("derivative_of_tau_cmd", request.derivative_outputs.tau_cmd ? "true" : "false");
  values.set("check_inputs", request.check_inputs);
  values.set("check_inputs_value", request.check_inputs ? "true" : "false");
  values.set("returns_every_output", request.trace.outputs.all() ? "true" : "false");
  values.set("op_counts", tally.op_lines);
  return values;
}

// Where the set's identity goes while it is computed: a byte that neither a template nor any
// text from the input (inert_text escapes control bytes) can hold.
constexpr char kOutputSetSlot[] = "\x01";

// `text` with every `slot` replaced by `value`.
std::string filled(std::string text, const std::string& slot, const std::string& value) {
  for (auto at = text.find(slot); at != std::string::npos; at = text.find(slot, at + value.size()))
    text.replace(at, slot.size(), value);
  return text;
}

// The files of one scene, each from its template (templates/): the header, the source (every
// function for one state and for a Batch of states), the CUDA kernels and launchers, the CMake
// snippet. Each carries the set's identity (`output_set`), a hash of the four texts as they read
// with the slot in its place: the same scene gives the same bytes, two that differ anywhere two
// identities that the files check against each other.
std::vector<EmittedFile> render_files(const std::string& stem, data& values) {
  values.set("header_name", stem + ".hpp");
  values.set("source_name", stem + ".cpp");
  values.set("target", stem);
  values.set("output_set", kOutputSetSlot);
  std::vector<EmittedFile> files;
  std::string set_text;
  for (const std::string extension : {"hpp", "cpp", "cu", "cmake"}) {
    files.push_back({stem + "." + extension, render("solver." + extension + ".mustache", values)});
    set_text += files.back().name + '\0' + files.back().text + '\0';
  }
  const std::string identity = "0x" + io::fnv1a64(set_text) + "ull";
  for (auto& file : files) file.text = filled(std::move(file.text), kOutputSetSlot, identity);
  return files;
}

}  // namespace

std::string file_stem(const std::string& solver_namespace) {
  std::string stem = solver_namespace;
  for (std::size_t at = stem.find("::"); at != std::string::npos; at = stem.find("::", at + 2)) stem.replace(at, 2, "__");
  return stem;
}

EmittedSolver emit_solver(const model::Chain& chain, const EmitRequest& request) {
  EmittedSolver result;
  FileTally tally;
  data variants{data::type::list};
  for (const std::string& scalar : request.scalars) variants.push_back(variant_values(chain, request, scalar, result, tally));
  const Fusion fusion = fusion_of(result.costs);
  const std::string joint_line = joint_inertia_line(chain, request);
  result.choices = emitter_choices(request, tally, joint_line, fusion);
  data values = file_values(chain, request, tally, joint_line, fusion);
  values.set("variants", variants);
  result.files = render_files(file_stem(request.solver_namespace), values);
  return result;
}

}  // namespace sweepgen::emit
