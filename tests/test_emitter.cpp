// The emitter leaves out what a scene does not need, tags every stored quantity with its
// equation, and prints numbers that read back exactly.
#include <gtest/gtest.h>

#include <random>
#include <regex>
#include <set>

#include "emit/equations.hpp"
#include "emit/function_plan.hpp"
#include "emit/literal.hpp"
#include "emit/solver_emitter.hpp"
#include "support/bundled_robots.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen {
namespace {

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
    const std::regex named(R"(^(.+?)(_\d+)?_\d+(_term(_\d+)?)?$)");
    const std::regex function_of_input(R"(^(sin|cos)_q_\d+$)");
    ASSERT_FALSE(plan.carried_name.empty());
    std::set<std::string> names;
    for (const auto& [node, name] : plan.carried_name) {
      EXPECT_TRUE(names.insert(name).second) << "two State members named " << name;
      std::smatch m;
      if (std::regex_match(name, function_of_input)) continue;
      ASSERT_TRUE(std::regex_match(name, m, named)) << name;
      EXPECT_TRUE(arrays.count(m[1])) << name << ": no array " << m[1];
    }
    const emit::EmitRequest emit_request{"scene", {"double"}, false, request({{"push", "panda_hand"}}, nc), "test"};
    const auto emitted = emit::emit_solver(chain, emit_request);
    for (const auto& file : emitted.files) {
      EXPECT_EQ(file.text.find("carried_"), std::string::npos) << file.name;
      if (file.name != "scene.cpp") continue;
      // Between two banners or array comments there is code; no statement precedes the first.
      const auto body = file.text.find("void outward(");
      const auto first_statement = file.text.find("  const double", body);
      const auto first_banner = file.text.find("  // ==== outward sweep", body);
      EXPECT_LT(first_banner, first_statement);
      if (nc > 0) {
        // The constraint multipliers' factorisation sits under the banner of nu.
        const auto solve = file.text.find("void solve_original(");
        const auto nu_banner = file.text.find("  // nu: ", solve);
        const auto nu_store = file.text.find("out.nu[0] =", solve);
        const auto last_banner_before = file.text.rfind("  // ", nu_store);
        EXPECT_EQ(last_banner_before, nu_banner);
      }
    }
  }
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
  EXPECT_EQ(emit::literal(std::numeric_limits<double>::infinity(), "double"), "std::numeric_limits<double>::infinity()");
}

}  // namespace
}  // namespace sweepgen
