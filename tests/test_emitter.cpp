// The emitter leaves out what a scene does not need, tags every stored quantity with its
// equation, and prints numbers that read back exactly; what it emits, compiled and run, computes
// what the reference solver computes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>
#include <type_traits>

#include "emit/equations.hpp"
#include "emit/function_plan.hpp"
#include "emit/literal.hpp"
#include "emit/solver_emitter.hpp"
#include "report/compiled_solver.hpp"
#include "report/measure.hpp"
#include "report/stability_errors.hpp"
#include "scene/scene.hpp"
#include "solver/derivative_seeds.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/compiled_scene.hpp"
#include "support/oracle_problem.hpp"
#include "support/text_pattern.hpp"
#include "support/random_chain.hpp"
#include "support/same_bits.hpp"
#include "support/state_count.hpp"
#include "support/temp_dir.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

const std::vector<solver::Policy> kAllPolicies = {solver::Policy::original, solver::Policy::prioritize_external,
                                                  solver::Policy::saturate, solver::Policy::saturate_exact};

model::Chain panda() { return test::load_bundled(test::bundled_robots().front()); }

symbolic::TraceRequest request(std::vector<solver::ExternalForceDriver> external, std::size_t nc) {
  symbolic::TraceRequest r;
  r.layout.torques = {"tau_ff"};
  r.layout.external_forces = std::move(external);
  r.layout.constraints = nc;
  r.layout.decompose_all();
  r.policies = kAllPolicies;
  r.epsilon = std::numeric_limits<double>::epsilon();
  return r;
}

// Operations (non-leaf nodes) the outputs of every policy need, and how many of them depend
// on an external-force input.
std::pair<std::size_t, std::size_t> needed_operations(const symbolic::Trace& trace) {
  const auto& g = trace.graph;
  std::vector<bool> external(g.size(), false), needed(g.size(), false);
  for (symbolic::NodeId id = 0; id < g.size(); ++id) {
    const auto& n = g.node(id);
    if (n.op == symbolic::Op::input) external[id] = trace.inputs[n.input].quantity == symbolic::Quantity::external_force;
    for (int k = 0; k < symbolic::arity(n.op); ++k) external[id] = external[id] || external[n.args[k]];
  }
  std::vector<symbolic::NodeId> stack;
  for (const auto& f : trace.fields)
    if (f.output) stack.push_back(f.node);
  while (!stack.empty()) {
    const auto id = stack.back();
    stack.pop_back();
    if (needed[id]) continue;
    needed[id] = true;
    const auto& n = g.node(id);
    for (int k = 0; k < symbolic::arity(n.op); ++k) stack.push_back(n.args[k]);
  }
  std::size_t operations = 0, external_operations = 0;
  for (symbolic::NodeId id = 0; id < g.size(); ++id) {
    const auto op = g.node(id).op;
    if (!needed[id] || op == symbolic::Op::constant || op == symbolic::Op::input) continue;
    ++operations;
    external_operations += external[id] ? 1 : 0;
  }
  return {operations, external_operations};
}

std::size_t full_solve_operations(const model::Chain& chain, const symbolic::TraceRequest& r) {
  const emit::EmitRequest emit_request{"scene", {"double"}, false, r, "test"};
  for (const auto& c : emit::emit_solver(chain, emit_request).costs)
    if (c.function == "full solve_original") return c.ops.total();
  return 0;
}

// Without external forces no operation depends on them, and the code is smaller than with
// them: at least the operations that do not involve them, at most all of those with them
// (each operation that mixed an external force in has a cheaper twin without it).
TEST(Emitter, ASceneWithoutExternalForcesHasNoExternalForceOperations) {
  const model::Chain chain = panda();
  for (std::size_t nc : {0u, 3u, 6u}) {
    const auto with_request = request({{"push", "panda_hand"}, {"contact", "panda_link5"}}, nc);
    const auto without_request = request({}, nc);
    const auto [with_total, with_external] = needed_operations(symbolic::trace_solver(chain, with_request));
    const auto [without_total, without_external] = needed_operations(symbolic::trace_solver(chain, without_request));
    EXPECT_EQ(without_external, 0u);
    EXPECT_GT(with_external, 0u);
    EXPECT_GE(without_total, with_total - with_external) << "Nc=" << nc;
    EXPECT_LT(without_total, with_total) << "Nc=" << nc;
    // And the emitted operation counts say the same.
    EXPECT_LT(full_solve_operations(chain, without_request), full_solve_operations(chain, with_request)) << "Nc=" << nc;
  }
}

TEST(Emitter, EveryStoredArrayHasAnEquation) {
  const auto trace = symbolic::trace_solver(panda(), request({{"push", "panda_hand"}}, 6));
  std::set<std::string> arrays;
  for (const auto& f : trace.fields) arrays.insert(f.array);
  EXPECT_GT(arrays.size(), 20u);
  for (const auto& array : arrays) EXPECT_NO_THROW(emit::equation_of(array)) << array;
  EXPECT_THROW(emit::equation_of("no_such_array"), std::logic_error);
}

// Every value a later function reads is a State member named from the math: the field it is
// (array_body_component, with the policy in front for a solve's own), sin/cos of the input it
// is, or a term of the first field whose expression reaches it; and every block of statements
// sits under a banner naming the quantity it computes.
TEST(Emitter, StateMembersAndBannersAreNamedFromTheMath) {
  const model::Chain chain = panda();
  for (std::size_t nc : {0u, 6u}) {
    const auto trace = symbolic::trace_solver(chain, request({{"push", "panda_hand"}}, nc));
    const emit::Plan plan = emit::make_plan(trace, false);
    std::set<std::string> arrays;
    for (const auto& f : trace.fields) arrays.insert((emit::is_state_field(f) ? "" : f.group + "_") + f.array);
    const test::Pattern named(R"(^(.+?)(_\d+)?_\d+(_term(_\d+)?)?$)");
    const test::Pattern function_of_input(R"(^(sin|cos)_q_\d+$)");
    ASSERT_FALSE(plan.carried_name.empty());
    std::set<std::string> names;
    for (const auto& [node, name] : plan.carried_name) {
      EXPECT_TRUE(names.insert(name).second) << "two State members named " << name;
      test::Match m;
      if (function_of_input.matches(name)) continue;
      ASSERT_TRUE(named.matches(name, m)) << name;
      EXPECT_TRUE(arrays.count(m[1])) << name << ": no array " << m[1];
    }
    const emit::EmitRequest emit_request{"scene", {"double"}, false, request({{"push", "panda_hand"}}, nc), "test"};
    const auto emitted = emit::emit_solver(chain, emit_request);
    for (const auto& file : emitted.files) {
      EXPECT_EQ(file.text.find("carried_"), std::string::npos) << file.name;
      if (file.name != "scene.cpp") continue;
      // Between two banners or array comments there is code; no statement precedes the first.
      const auto body = file.text.find("bool outward_of(");
      const auto first_statement = file.text.find("  const S ", body);
      const auto first_banner = file.text.find("  // ==== outward sweep", body);
      EXPECT_LT(first_banner, first_statement);
      if (nc > 0) {
        // The constraint multipliers' factorisation sits under the banner of nu (or inside the
        // if/else of its path, C4).
        const auto solve = file.text.find("bool solve_original_of(");
        EXPECT_NE(file.text.find("  // nu: ", solve), std::string::npos);
        const auto nu_store = file.text.find("out.nu[0] =", solve);
        const auto last_banner_before = file.text.rfind("  // ", nu_store);
        const auto line_start = file.text.rfind('\n', last_banner_before) + 1;
        const std::string line = file.text.substr(line_start, file.text.find('\n', line_start) - line_start);
        EXPECT_TRUE(line.find("// nu: ") != std::string::npos || line.find("// (C4)") != std::string::npos) << line;
      }
    }
  }
}

// constraint_rows: auto keeps (I2) or (I6) by operation count, the columns' weighted by 21/20 once
// they carry more than two directions (they spill: solver_emitter.cpp, rows_cost). The header's
// line states both counts and the choice; the choice must follow from them, and the Panda's
// six-direction scene (columns ahead by under 5 %, bench/README.md) must be one where the weight
// decides.
TEST(Emitter, AutoConstraintRowsWeighSpillingColumns) {
  const model::Chain chain = panda();
  const test::Pattern columns_count(R"(columns F\^A_cstr,i inward \(I2\) \((\d+) operations(, (\d+) counting two lanes as one)?\))");
  const test::Pattern rows_count(R"(rows r_i outward \(I6\) \((\d+) operations\))");
  std::size_t decided_by_weight = 0, in_lanes = 0;
  for (const bool fixed : {false, true})
    for (std::size_t nc : {1u, 2u, 3u, 6u}) {
      symbolic::TraceRequest r = request({{"push", "panda_hand"}}, nc);
      if (fixed) {  // unit directions along the axes of panda_hand: folded, no lanes
        std::vector<spatial::Force<double>> axes(nc);
        for (std::size_t k = 0; k < nc; ++k) (k < 3 ? axes[k].moment : axes[k].force)[k % 3] = 1;
        r.layout.sets = {solver::ConstraintSet::on("", nc, axes)};
      }
      const emit::EmitRequest emit_request{"scene", {"double"}, false, r, "test"};
      const auto choices = emit::emit_solver(chain, emit_request).choices;
      const auto line = std::find_if(choices.begin(), choices.end(),
                                     [](const std::string& c) { return c.rfind("Constraint rows", 0) == 0; });
      ASSERT_NE(line, choices.end()) << "Nc=" << nc;
      test::Match c, rows_match;
      ASSERT_TRUE(columns_count.search(*line, c)) << *line;
      ASSERT_TRUE(rows_count.search(*line, rows_match)) << *line;
      const double rows = std::stod(rows_match[1]);
      // Run-time directions (two or more) are computed in lanes: the columns cost what the line
      // states counting two lanes as one, unweighted; else their count, weighted past two.
      const bool lanes = c.matched(3);
      EXPECT_EQ(lanes, !fixed && nc >= 2) << *line;
      const double columns = lanes ? std::stod(c[3]) : std::stod(c[1]) * (nc > 2 ? 21.0 / 20.0 : 1.0);
      const bool chose_rows = line->find(": rows r_i outward") != std::string::npos;
      EXPECT_EQ(chose_rows, rows < columns) << *line;
      EXPECT_EQ(line->find("weighted by 21/20") != std::string::npos, !lanes && nc > 2) << *line;
      if (chose_rows && std::stod(c[1]) < rows) ++decided_by_weight;
      in_lanes += lanes && !chose_rows ? 1 : 0;
    }
  EXPECT_GE(decided_by_weight, 1u);
  EXPECT_GE(in_lanes, 1u);
}

// The operation count of `function` ("full solve_original", "derivatives_original", ...) and the
// header's text, as emitted for `r` (namespace "scene").
std::pair<std::size_t, std::string> operations_and_header(const model::Chain& chain, const emit::EmitRequest& r,
                                                          const std::string& function) {
  const emit::EmittedSolver solver = emit::emit_solver(chain, r);
  std::size_t operations = 0;
  for (const auto& cost : solver.costs)
    if (cost.function == function) operations = cost.ops.total();
  const auto header = std::find_if(solver.files.begin(), solver.files.end(),
                                    [](const emit::EmittedFile& f) { return f.name == "scene.hpp"; });
  return {operations, header == solver.files.end() ? std::string() : header->text};
}

// derivatives: [..] returns the Jacobians listed and computes nothing for the others: on the Panda
// with six directions, the derivative function's operations fall with each Jacobian left out
// (τcmd's needs its own tangent sweep of the constraint wrenches), its Derivatives has no member
// for what is left out, and the header's flat size is the layout's (DerivativeOutputs).
TEST(Emitter, DerivativesLeftOutAreNotComputed) {
  const model::Chain chain = panda();
  const std::size_t n = chain.dof(), nc = 6;
  const auto emitted = [&](const solver::DerivativeOutputs& outputs) {
    emit::EmitRequest r{"scene", {"double"}, false, request({}, nc), "test"};
    r.trace.policies = {solver::Policy::original};
    r.derivatives = true;
    r.derivative_outputs = outputs;
    return operations_and_header(chain, r, "derivatives_original");
  };
  const auto [all, all_header] = emitted({true, true, true});
  const auto [without_tau_cmd, without_tau_cmd_header] = emitted({true, true, false});
  const auto [qdd_only, qdd_only_header] = emitted({true, false, false});
  EXPECT_GT(all, 0u);
  EXPECT_LT(without_tau_cmd, all);
  EXPECT_LT(qdd_only, without_tau_cmd);
  EXPECT_NE(all_header.find("Scalar d_tau_cmd["), std::string::npos);
  EXPECT_EQ(without_tau_cmd_header.find("Scalar d_tau_cmd["), std::string::npos);
  EXPECT_NE(without_tau_cmd_header.find("Scalar d_nu["), std::string::npos);
  EXPECT_EQ(qdd_only_header.find("Scalar d_nu["), std::string::npos);
  const solver::DerivativeColumns columns{n, nc, {}};
  for (const auto& [outputs, header] : {std::pair{solver::DerivativeOutputs{true, true, true}, all_header},
                                        {solver::DerivativeOutputs{true, false, false}, qdd_only_header}})
    EXPECT_NE(header.find("constexpr int derivative_flat_out_size = " + std::to_string(outputs.flat_out_size(columns)) + ";"),
              std::string::npos);
  std::cout << "[derivative outputs] operations of derivatives_original, Panda Nc = 6: all " << all
            << ", qdd and nu " << without_tau_cmd << ", qdd " << qdd_only << std::endl;
}

// outputs: [..] (scene key): the solves return the results listed and compute nothing for the
// others beyond what those need: on the Panda with six directions, leaving τcmd, τctrl and Ẍ_tip out
// takes τcmd's inward sweep of the constraint wrenches and the second pass's Ẍ_tip (R1) out of the
// full solve, its Solution has no member for them, and the header's flat size is the layout's.
TEST(Emitter, OutputsLeftOutAreNotComputed) {
  const model::Chain chain = panda();
  const std::size_t n = chain.dof(), nc = 6;
  const auto emitted = [&](const solver::SolveOutputs& outputs) {
    emit::EmitRequest r{"scene", {"double"}, false, request({}, nc), "test"};
    r.trace.policies = {solver::Policy::original};
    r.trace.outputs = outputs;
    return operations_and_header(chain, r, "full solve_original");
  };
  const solver::SolveOutputs qdd_nu{true, false, false, true, false, false};
  const auto [all, all_header] = emitted({});
  const auto [lean, lean_header] = emitted(qdd_nu);
  EXPECT_LT(lean, all);
  for (const char* member : {"Scalar tau_cmd[", "Scalar tau_ctrl[", "Scalar tip_acceleration["}) {
    EXPECT_NE(all_header.find(member), std::string::npos) << member;
    EXPECT_EQ(lean_header.find(member), std::string::npos) << member;
  }
  EXPECT_NE(lean_header.find("Scalar qdd["), std::string::npos);
  EXPECT_NE(lean_header.find("Scalar nu["), std::string::npos);
  EXPECT_NE(lean_header.find("constexpr bool returns_every_output = false;"), std::string::npos);
  solver::DriverLayout layout = request({}, nc).layout;
  for (const auto& [outputs, header] : {std::pair{solver::SolveOutputs{}, all_header}, {qdd_nu, lean_header}})
    EXPECT_NE(header.find("constexpr int flat_out_size = " +
                          std::to_string(solver::FlatLayout::of(layout, n, false, outputs).out_size()) + ";"),
              std::string::npos);
  std::cout << "[solve outputs] operations of the full solve_original, Panda Nc = 6: all " << all << ", qdd and nu "
            << lean << std::endl;
}

TEST(Emitter, LiteralsRoundTrip) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int k = 0; k < 100000; ++k) {
    const double value = std::ldexp(mantissa(rng), exponent(rng) / 1);
    const std::string d = emit::literal(value, "double");
    EXPECT_EQ(std::strtod(d.c_str(), nullptr), value) << d;
    EXPECT_NE(d.find_first_of(".e"), std::string::npos) << d;
    const float f = static_cast<float>(std::ldexp(mantissa(rng), exponent(rng) / 10));
    const std::string fl = emit::literal(f, "float");
    ASSERT_EQ(fl.back(), 'f');
    EXPECT_EQ(std::strtof(fl.c_str(), nullptr), f) << fl;
  }
  EXPECT_EQ(emit::literal(1.0, "double"), "1.0");
  EXPECT_EQ(emit::literal(-2.0, "float"), "-2.0f");
  EXPECT_EQ(emit::literal(1e300, "double"), "1e+300");
  EXPECT_EQ(emit::literal(std::numeric_limits<double>::infinity(), "double"), "HUGE_VAL");
  EXPECT_EQ(emit::literal(-std::numeric_limits<double>::infinity(), "float"), "-HUGE_VALF");
}

// ---- The emitted solver, compiled and run ---------------------------------------------------
// Small scenes that together take every branch of the emitter: Nc 0, 1, 3, 6; directions given
// at run time and fixed in the scene; torque drivers, external forces on a middle link and on
// the tip; composed, decomposed and grouped tracks; revolute and prismatic joints; a robot whose
// fixed links are lumped (panda: link8, hand, locked fingers); every policy; the damped
// factorisation, expose: all and check_inputs: false once each. Each is generated, compiled by
// the system compiler and loaded as `sweepgen report` does (report/compiled_solver.hpp: its
// baseline flags, -O2 for x86-64; ~0.3–2 s of CPU per scene) and its double solve of every
// policy of the scene is run on random states against ReferenceSolver<double>. (The float code is
// compiled too, the wrapper needs it, but not run here: generated_scene_tests checks the bundled
// scenes' float solvers.)
struct EmitterCase {
  std::string name;  // also the solver's namespace
  model::Chain chain;
  scene::Scene scene;
};

model::Chain random_chain(unsigned seed, std::size_t dof) { return test::RandomChainGenerator(seed).chain(dof); }

// A scene over `chain` with the drivers of `layout` (tracks built), as report_scene makes it
// (double and float: the compiled wrapper loads both) with `policies`.
scene::Scene case_scene(const std::string& name, const model::Chain& chain, solver::DriverLayout layout,
                        std::vector<solver::Policy> policies) {
  scene::Scene s;
  s.solver = name;
  s.chain.urdf = chain.source;
  s.chain.floating_base = chain.floating_base;
  s.layout = std::move(layout);
  s = report::report_scene(std::move(s));
  s.policies = std::move(policies);
  solver::validate(s.layout, chain, name);
  return s;
}

solver::DriverLayout drivers(std::vector<std::string> torques, std::vector<solver::ExternalForceDriver> external,
                             std::size_t constraints) {
  solver::DriverLayout layout;
  layout.torques = std::move(torques);
  layout.external_forces = std::move(external);
  layout.constraints = constraints;
  return layout;
}

std::vector<EmitterCase> make_emitter_cases() {
  using solver::Policy;
  std::vector<EmitterCase> cases;

  // Nc = 0, decomposed, every policy, no NaN/Inf checks.
  {
    const model::Chain chain = random_chain(21, 4);
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_tip", chain.tip_link}}, 0);
    layout.decompose_all();
    scene::Scene s = case_scene("random_nc0", chain, std::move(layout), kAllPolicies);
    s.check_inputs = false;
    cases.push_back({"random_nc0", chain, std::move(s)});
  }
  // Nc = 1 fixed in the scene (not along an axis), loads on a middle link and on the lumped tool,
  // grouped tracks: [bias, tau_ff], [f_mid, f_tip].
  {
    const model::Chain chain = test::load_bundled(test::bundled_robots().back());
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_mid", "link2"}, {"f_tip", "tool"}}, 1);
    layout.tracks = {solver::Track{"bias", true, {0}, {}}, solver::Track{"f_mid", false, {}, {0, 1}}};
    scene::Scene s = case_scene("planar_nc1_fixed", chain, std::move(layout), kAllPolicies);
    s.layout.sets = {solver::ConstraintSet::on("", 1, {spatial::Force<double>{{0, 0, 0.6}, {0.8, 0, 0}}})};
    cases.push_back({"planar_nc1_fixed", chain, std::move(s)});
  }
  // Nc = 3 at run time, two torque instances and a load on a middle link, composed, expose: all.
  {
    const model::Chain chain = random_chain(33, 5);
    solver::DriverLayout layout = drivers({"tau_ff", "tau_2"}, {{"f_mid", "link3"}}, 3);
    layout.compose_all();
    scene::Scene s = case_scene("random_nc3", chain, std::move(layout), {Policy::original, Policy::saturate});
    s.expose_all = true;
    cases.push_back({"random_nc3", chain, std::move(s)});
  }
  // Nc = 6 at run time on a robot with lumped fixed links, decomposed.
  {
    const model::Chain chain = panda();
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_mid", "panda_link4"}, {"f_tip", "panda_hand"}}, 6);
    layout.decompose_all();
    cases.push_back({"panda_nc6", chain,
                     case_scene("panda_nc6", chain, std::move(layout), {Policy::original, Policy::prioritize_external})});
  }
  // Constraint sets on three links of a robot with lumped links: two run-time directions on
  // panda_link4 (an elbow), one fixed on the lumped hand, one run-time on panda_link6; decomposed.
  {
    const model::Chain chain = panda();
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_mid", "panda_link4"}}, 4);
    layout.sets = {solver::ConstraintSet::on("panda_link4", 2),
                   solver::ConstraintSet::on("panda_hand", 1, {spatial::Force<double>{{0, 0, 0}, {0, 0, 1}}}),
                   solver::ConstraintSet::on("panda_link6", 1)};
    layout.decompose_all();
    cases.push_back({"panda_sets", chain,
                     case_scene("panda_sets", chain, std::move(layout),
                                {Policy::original, Policy::prioritize_external, Policy::saturate_exact})});
  }
  // A random tree (each body on a random earlier one) with a constraint set on its tip and one on
  // another branch's end, a load on the first body; decomposed.
  {
    const model::Chain chain = test::RandomChainGenerator(71).tree(9);
    if (chain.is_chain() || chain.branch_tips.empty()) throw std::logic_error("random_tree: seed 71 drew no branches");
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_first", chain.bodies[1].link}}, 3);
    layout.sets = {solver::ConstraintSet::on(chain.tip_link, 2), solver::ConstraintSet::on(chain.branch_tips.front(), 1)};
    if (!solver::structurally_overdetermined(layout.sets, chain).empty()) throw std::logic_error("random_tree: sets");
    layout.decompose_all();
    cases.push_back({"random_tree", chain,
                     case_scene("random_tree", chain, std::move(layout), {Policy::original, Policy::saturate})});
  }
  // A random tree on a floating base (F5: q leads with world_R_base, six base coordinates), a
  // run-time set on its tip and a load on the root body; composed.
  {
    const model::Chain chain = test::RandomChainGenerator(83).floating_tree(5);
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_root", chain.bodies[6].link}}, 3);
    layout.sets = {solver::ConstraintSet::on(chain.tip_link, 3)};
    layout.compose_all();
    cases.push_back({"random_floating_tree", chain,
                     case_scene("random_floating_tree", chain, std::move(layout),
                                {Policy::original, Policy::saturate_exact})});
  }
  // Nc = 6 fixed (the tip's full acceleration), damped factorisation, grouped: [f_tip], [bias, tau_ff].
  {
    const model::Chain chain = random_chain(45, 6);
    solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_tip", chain.tip_link}}, 6);
    layout.tracks = {solver::Track{"f_tip", false, {}, {0}}, solver::Track{"bias", true, {0}, {}}};
    scene::Scene s =
        case_scene("random_nc6_fixed", chain, std::move(layout), {Policy::original, Policy::saturate_exact});
    s.layout.sets = {solver::ConstraintSet::on("", 6)};
    for (int k = 0; k < 6; ++k) {
      spatial::Force<double> axis;
      (k < 3 ? axis.moment : axis.force)[k % 3] = 1;
      s.layout.sets.front().fixed.push_back(axis);
    }
    s.constraint_factorisation = solver::ConstraintFactorisation::damped;
    cases.push_back({"random_nc6_fixed", chain, std::move(s)});
  }
  return cases;
}

const std::vector<EmitterCase>& emitter_cases() {
  static const std::vector<EmitterCase> cases = make_emitter_cases();
  return cases;
}


template <class Vector>
std::vector<report::Precise> precise(const Vector& v) {
  return std::vector<report::Precise>(v.data(), v.data() + v.size());
}

// The binary128 referee of a state with its answer replaced by ReferenceSolver<double>'s: what
// report::judge needs to measure the generated answer against the reference's, with the scales
// and the κ of the stability tests (report/stability_errors.hpp).
report::Truth reference_as_referee(report::Truth truth, const solver::Solution<double>& reference, unsigned status) {
  truth.qdd = precise(reference.qdd);
  truth.tau_cmd = precise(reference.tau_cmd);
  truth.nu = precise(reference.nu);
  truth.status = status;
  return truth;
}

// The terms the policy `saturate` sums into τcmd (T2, solver/commanded_torque.hpp):
// RNEA(q, q̇, q̈; F_ext) = M q̈ + b(q, q̇) − Σ J^T F_ext, besides τff. Where they cancel (a prismatic
// joint holding links against gravity with a small net force) τcmd is rounded relative to them,
// not to itself; M q̈ is at most the sum of the others and τcmd. From the dense oracle.
std::vector<std::vector<report::Precise>> inverse_dynamics_terms(const test::Oracle& oracle, const scene::Scene& s,
                                                                 const report::Problem& p) {
  std::vector<test::Oracle::ExternalWrench> external;
  for (std::size_t e = 0; e < p.wrenches.size(); ++e)
    external.push_back({s.layout.external_forces[e].link, test::to_six(p.wrenches[e])});
  const test::OracleVec q = test::to_long(p.q);
  return {precise(p.tau_ff), precise(oracle.bias(q, test::to_long(p.qd))), precise(oracle.external_torque(q, external))};
}

// |generated − reference| / scale <= kEmittedErrorFactor · eps · κ for q̈, τcmd and ν on every
// state with κ <= kIllConditioned (κ and the scales of report/stability_errors.hpp; τcmd of
// `saturate` against its (T2) terms, inverse_dynamics_terms). The two run the same traced
// operations in the same order but for
//  - the trace's constant folding (x·1, x + 0, products of constants: a rounding dropped or
//    moved) and
//  - the compiler's contraction of a·b + c into one FMA (where the target has FMA, as the
//    report's x86-64-v3 build does; g++ contracts by default), which drops the rounding of a·b;
// each such site perturbs one intermediate by at most one rounding, as each of the reference's
// own operations does. To first order the outputs move by Σ over the sites of (sensitivity to
// that intermediate) · (its perturbation): the sum that bounds the reference's own rounding
// error has a term for every operation, this one for the few differing sites only, so it is at
// most that bound, which test_stability asserts as 100 eps κ (kErrorFactor; measured <= 12).
// Measured here (x86-64 baseline, no FMA; the printed lines): <= 6.8 eps κ on the chains
// (random_nc3), 2.0 on the floating tree, planar_nc1_fixed bit-identical: folding is the whole difference; 31.8 on the
// 9-joint random tree (state 66: q̈ differs by 2.8e-14 at κ = 3.9, a κ that leaves out cond(M),
// which random inertias on a branched tree make large: the sensitivity the sum above multiplies). Built with FMA
// (-march=native, an earlier revision) the worst was 14 eps κ. 40 leaves ~3x headroom and stays below the reference's own
// bound; a flipped sign or a dropped term is O(1) relative, ~1e13 times the tolerance. Absolute
// ceiling: the states compared have κ <= kIllConditioned = 1e6, so the tolerance never exceeds
// 40 · 2.2e-16 · 1e6 ≈ 9e-9; the states beyond are counted, printed, and at most
// kIllConditionedShare of them.
constexpr double kEmittedErrorFactor = 40;
// Beyond this κ the states are counted apart: rounding is amplified by κ in any solver.
constexpr double kIllConditioned = 1e6;
// Panda with 6 random directions: E^A_cstr,0 = αᵀ (tip's inverse inertia) α is near-singular for
// some states (34 of 200 at this seed, 2 of the first 20 that the sanitizer build draws); the
// random chains with fixed directions have 1 of 200, the others none.
constexpr double kIllConditionedShare = 0.25;

// The state of one policy's largest difference.
struct Worst {
  double ratio = 0;  // |generated − reference| / scale, in eps κ
  std::size_t state = 0;
  report::StateJudgement judgement;
};

class EmittedSolver : public ::testing::TestWithParam<std::size_t> {};

TEST_P(EmittedSolver, CompiledAndRunMatchesTheReference) {
  const EmitterCase& c = emitter_cases().at(GetParam());
  test::TempDir dir;
  const report::CompiledSolver compiled = test::compile_scene(c.scene, c.chain, dir.path());

  const auto problems = report::random_problems(c.scene, c.chain, test::state_count(200), 17);
  const auto truth = report::precise_reference(c.scene, c.chain, problems);
  const test::Oracle oracle(c.chain, c.scene.gravity);
  report::TimingOptions untimed;
  untimed.repetitions = 0;
  const double eps = std::numeric_limits<double>::epsilon();
  for (const solver::Policy policy : c.scene.policies) {
    const std::string where = c.name + " " + solver::name(policy);
    const auto generated = report::measure_generated<double>(compiled.solve_f64_of.at(policy), "double",
                                                             c.scene.flat_layout(c.chain), problems, untimed);
    solver::SolverOptions traced_options = c.scene.solver_options();  // the rows as the generator formed them
    traced_options.constraint_rows = compiled.constraint_rows;
    solver::ReferenceSolver<double> reference(c.chain, c.scene.layout, traced_options);
    Worst worst;
    double max_ulps = 0;  // the largest difference in ulps of its vector's scale (its largest entry)
    double max_residual = 0;  // the largest constraint residual / (eps κ)
    std::size_t ill_conditioned = 0, status_differs = 0;
    for (std::size_t k = 0; k < problems.size(); ++k) {
      const auto& solution = reference.run(problems[k], policy);
      const report::Truth referee = reference_as_referee(truth[k], solution, reference.status());
      const report::Outcome& outcome = generated.outcomes[k];
      report::StateJudgement j =
          report::judge(outcome, referee, problems[k], c.chain, std::numeric_limits<double>::max());
      if (policy == solver::Policy::saturate)
        j.tau = report::joint_relative_error(outcome.tau_cmd, referee.tau_cmd, c.chain,
                                             inverse_dynamics_terms(oracle, c.scene, problems[k]));
      // Beyond kIllConditioned a pivot can sit within rounding of the tolerance, and the two may
      // decide it differently; below, a kept pivot is >= E_kk / 1e6, far above the tolerance (and a
      // torque within rounding of its effort limit, where saturation could flip, has odds ~1e-13).
      if (!(j.kappa() <= kIllConditioned)) {
        ++ill_conditioned;
        continue;
      }
      status_differs += j.status != j.exact_status ? 1 : 0;
      if (!(j.error() / (eps * j.kappa()) <= worst.ratio)) worst = {j.error() / (eps * j.kappa()), k, j};
      // The generated link accelerations (tip_acceleration, or set_acceleration for listed sets)
      // meet α_kᵀ Ẍ_link(k) = β_k where every direction is kept: an exact answer's residual is
      // 0, the original policy's (refined by (R1) from this very residual) carries the rounding of
      // q̈ bounded as above, the same factor and ceiling (measured <= 22 eps κ, planar_nc1_fixed).
      // Other policies and the damped factorisation leave a residual by design.
      if (j.full_rank()) max_residual = std::max(max_residual, j.constraint_residual / (eps * j.kappa()));
      max_ulps = std::max(max_ulps, j.error() / eps);
    }
    std::printf("[emitted] %s: %zu states, %zu with kappa > %.0e; max |generated - reference| %.3g ulp, "
                "max / (eps kappa) %.2f, max residual / (eps kappa) %.2f\n",
                where.c_str(), problems.size(), ill_conditioned, kIllConditioned, max_ulps, worst.ratio, max_residual);
    if (policy == solver::Policy::original &&
        c.scene.constraint_factorisation == solver::ConstraintFactorisation::pivoted_ldlt) {
      EXPECT_LE(max_residual, kEmittedErrorFactor) << where;
    }
    EXPECT_LE(worst.ratio, kEmittedErrorFactor)
        << where << " state " << worst.state << ": relative difference qdd " << worst.judgement.qdd << " tau_cmd "
        << worst.judgement.tau << " nu " << worst.judgement.nu << ", kappa " << worst.judgement.kappa();
    EXPECT_EQ(status_differs, 0u) << where << ": status bits differ";
    EXPECT_LE(static_cast<double>(ill_conditioned), kIllConditionedShare * static_cast<double>(problems.size())) << where;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EmittedSolver, ::testing::Range<std::size_t>(0, emitter_cases().size()),
                         [](const auto& info) { return emitter_cases().at(info.param).name; });

// (C4)'s if/else as emitted: with the same direction given twice, E^A_cstr,0 is singular on every
// state, so the rule sends every state to the pivoted path, which drops one of the two
// (status_constraint_rank_deficient) and enforces the other. The natural-order factors would
// divide by a pivot of rounding size instead: an if/else emitted the wrong way round, or a
// pivoted path never taken, shows as a status or a ν the reference does not have. (Random states
// of the other scenes take the natural path, where both paths agree to rounding.)
TEST(Emitter, ASingularConstraintTakesThePivotedPath) {
  const model::Chain chain = panda();
  solver::DriverLayout layout = drivers({"tau_ff"}, {}, 2);
  const spatial::Force<double> up{{0, 0, 0}, {0, 0, 1}};
  layout.sets = {solver::ConstraintSet::on("panda_hand", 2, {up, up})};
  layout.compose_all();
  const scene::Scene s = case_scene("panda_twice_up", chain, std::move(layout), {solver::Policy::original});
  test::TempDir dir;
  const report::CompiledSolver compiled = test::compile_scene(s, chain, dir.path());
  const auto problems = report::random_problems(s, chain, test::state_count(50), 41);
  report::TimingOptions untimed;
  untimed.repetitions = 0;
  const auto generated = report::measure_generated<double>(compiled.solve_f64_of.at(solver::Policy::original), "double",
                                                           s.flat_layout(chain), problems, untimed);
  solver::SolverOptions options = s.solver_options();
  options.constraint_rows = compiled.constraint_rows;
  solver::ReferenceSolver<double> reference(chain, s.layout, options);
  for (std::size_t k = 0; k < problems.size(); ++k) {
    const auto& solution = reference.run(problems[k], solver::Policy::original);
    const report::Outcome& outcome = generated.outcomes[k];
    ASSERT_TRUE(reference.status() & solver::status_constraint_rank_deficient) << "state " << k;
    EXPECT_EQ(outcome.status, reference.status()) << "state " << k;
    // One multiplier carries the force along z, the other is 0: their sum is the reference's, and
    // so is q̈. The two run the same operations but for the trace's folding (EmittedSolver above);
    // its ceiling, kEmittedErrorFactor ε at the largest κ it judges (kIllConditioned), relative,
    // bounds them here too: ~9e-9, where a pivot of rounding size would make ν ~1e16 times larger.
    const double bound = kEmittedErrorFactor * std::numeric_limits<double>::epsilon() * kIllConditioned;
    const double sum = static_cast<double>(outcome.nu[0] + outcome.nu[1]);
    const double expected = solution.nu[0] + solution.nu[1];
    EXPECT_LE(std::abs(sum - expected), bound * std::max(1.0, std::abs(expected)))
        << "state " << k << ": " << sum << " vs " << expected;
    for (std::size_t i = 0; i < chain.dof(); ++i)
      EXPECT_LE(std::abs(static_cast<double>(outcome.qdd[i]) - solution.qdd[static_cast<Eigen::Index>(i)]),
                bound * std::max(1.0, solution.qdd.cwiseAbs().maxCoeff()))
          << "state " << k << " joint " << i;
  }
}

// The tests and the stability study compile generated code at -O0 (report::Optimisation::checked)
// on the claim that on the x86-64 baseline its numbers do not depend on -O: every operation is one
// SSE2 instruction rounding to its type, no fused multiply-add exists and -std=c++17 forbids
// contraction. Here the same solver (double and float solves, and the derivatives with their
// sines, cosines and square roots) is compiled at -O0 and at -O2, and every output of 200 states,
// status words included, must agree bit for bit.
TEST(Emitter, OptimisationDoesNotChangeTheNumbers) {
  const model::Chain chain = random_chain(51, 4);
  solver::DriverLayout layout = drivers({"tau_ff"}, {{"f_tip", chain.tip_link}}, 2);
  layout.decompose_all();
  scene::Scene s = case_scene("optimisation_levels", chain, std::move(layout), {solver::Policy::original});
  s.derivatives = true;
  test::TempDir deployed_dir, checked_dir;
  const report::CompiledSolver deployed =
      test::compile_scene(s, chain, deployed_dir.path(), report::Optimisation::deployed);
  const report::CompiledSolver checked = test::compile_scene(s, chain, checked_dir.path());
  ASSERT_NE(deployed.command, checked.command);

  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const std::size_t out_size = s.flat_layout(chain).out_size();
  const std::size_t derivative_out_size = s.derivative_outputs.flat_out_size(solver::DerivativeColumns{n, nc, {}});
  using test::flat_output;
  using test::same_bits;
  std::size_t differing = 0;
  const auto problems = report::random_problems(s, chain, 200, 31);
  for (const report::Problem& p : problems) {
    const std::vector<float> in_f32(p.flat.begin(), p.flat.end());
    const solver::Policy original = solver::Policy::original;
    differing += !same_bits(flat_output(deployed.solve_f64_of.at(original), p.flat, out_size),
                            flat_output(checked.solve_f64_of.at(original), p.flat, out_size));
    differing += !same_bits(flat_output(deployed.solve_f32, in_f32, out_size), flat_output(checked.solve_f32, in_f32, out_size));
    differing += !same_bits(flat_output(deployed.derivatives_f64_of.at(original), p.flat, derivative_out_size),
                            flat_output(checked.derivatives_f64_of.at(original), p.flat, derivative_out_size));
  }
  EXPECT_EQ(differing, 0u) << "of " << 3 * problems.size() << " outputs";
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
