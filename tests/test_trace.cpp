// The symbolic trace records exactly the reference sweeps: evaluating the traced graph in
// double reproduces every state field of ReferenceSolver<double>. Folding only applies exact
// identities (x*1, x+0, reordering of commutative operands), so the agreement is to a few
// ulps (tolerance 1e-13 relative, for operand orders Eigen may vectorise differently).
#include <gtest/gtest.h>

#include <map>

#include "solver/reference_solver.hpp"
#include "solver/state_fields.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen {
namespace {

using Key = std::tuple<std::string, std::string, int, int>;

solver::DriverLayout full_layout(const model::Chain& chain, std::size_t nc) {
  solver::DriverLayout layout;
  layout.torques = {"tau_ff", "tau_extra"};
  layout.external_forces = {{"push", chain.tip_link}, {"contact", chain.bodies[chain.dof() / 2 + 1].link}};
  layout.constraints = nc;
  layout.decompose_all();
  return layout;
}

TEST(Trace, GraphEvaluationReproducesTheReferenceSolver) {
  const std::vector<solver::Policy> policies = {solver::Policy::original, solver::Policy::prioritize_external,
                                                solver::Policy::saturate, solver::Policy::saturate_exact};
  test::RandomProblem random(7);
  double worst = 0;
  for (const auto& robot : test::bundled_robots()) {
    const model::Chain chain = test::load_bundled(robot);
    for (std::size_t nc : {0u, 3u, 6u}) {
      SCOPED_TRACE(robot.name + " Nc=" + std::to_string(nc));
      const solver::DriverLayout layout = full_layout(chain, nc);
      symbolic::TraceRequest request{layout, {}, policies, {}, std::numeric_limits<double>::epsilon()};
      const symbolic::Trace trace = symbolic::trace_solver(chain, request);

      for (int sample = 0; sample < 20; ++sample) {
        solver::ReferenceSolver<double> reference(chain, layout);
        const Eigen::VectorXd q = random.positions(chain), qd = random.velocities(chain);
        auto& d = reference.drivers();
        d.torques[0] = random.torques(chain, 2.0);  // large enough to saturate sometimes
        d.torques[1] = random.torques(chain, 0.1);
        for (auto& f : d.external_forces) f = random.wrench();
        for (std::size_t k = 0; k < nc; ++k) d.constraint_directions[k] = random.unit_direction();
        solver::ConstraintVector<double> beta(nc);
        for (std::size_t k = 0; k < nc; ++k) beta[k] = random.uniform(-1, 1);

        // The same values, by input name.
        std::map<std::string, double> by_name;
        for (std::size_t i = 0; i < chain.dof(); ++i) {
          by_name["q[" + std::to_string(i) + "]"] = q[i];
          by_name["qd[" + std::to_string(i) + "]"] = qd[i];
          for (std::size_t t = 0; t < 2; ++t)
            by_name["drivers." + layout.torques[t] + "[" + std::to_string(i) + "]"] = d.torques[t][i];
        }
        for (std::size_t e = 0; e < 2; ++e)
          for (int c = 0; c < 3; ++c) {
            by_name["drivers." + layout.external_forces[e].name + "[" + std::to_string(c) + "]"] = d.external_forces[e].moment[c];
            by_name["drivers." + layout.external_forces[e].name + "[" + std::to_string(c + 3) + "]"] = d.external_forces[e].force[c];
          }
        for (std::size_t k = 0; k < nc; ++k) {
          for (int c = 0; c < 3; ++c) {
            by_name["drivers.alpha[" + std::to_string(k) + "][" + std::to_string(c) + "]"] = d.constraint_directions[k].moment[c];
            by_name["drivers.alpha[" + std::to_string(k) + "][" + std::to_string(c + 3) + "]"] = d.constraint_directions[k].force[c];
          }
          by_name["beta[" + std::to_string(k) + "]"] = beta[k];
        }
        std::vector<double> inputs;
        for (const auto& in : trace.graph.inputs()) inputs.push_back(by_name.at(in.name));
        const std::vector<double> values = trace.graph.evaluate(inputs);

        std::map<Key, double> expected;
        const auto keep = [&expected](const std::string& group) {
          return [&expected, group](const std::string& array, int body, int component, double v) {
            expected[{group, array, body, component}] = v;
          };
        };
        reference.outward(q, qd);
        reference.decompose();
        solver::visit_fields(reference.kinematics(), keep("kinematics"));
        solver::visit_fields(reference.articulated(), layout, keep("articulated"));
        for (auto policy : policies) solver::visit_fields(reference.solve(policy, beta), policy, keep(solver::name(policy)));

        ASSERT_EQ(expected.size(), trace.fields.size());
        for (const auto& field : trace.fields) {
          const double want = expected.at({field.group, field.array, field.body, field.component});
          const double error = std::abs(values[field.node] - want) / std::max(1.0, std::abs(want));
          worst = std::max(worst, error);
          ASSERT_LE(error, 1e-13) << field.group << "." << field.array << "[" << field.body << "][" << field.component
                                  << "]: traced " << values[field.node] << ", reference " << want;
        }
      }
    }
  }
  std::cout << "trace vs reference: max relative difference " << worst << "\n";
}

// C++ leaves the order in which operands are evaluated open: g++ and clang trace `a*b + c*d`
// creating a*b or c*d first, so node ids differ between the two builds. Graph::canonical must
// give the same graph either way (the emitted code, and generated/, must not depend on the
// compiler that built sweepgen; the sanitize build, with clang, checks generated/ byte for byte).
TEST(Trace, CanonicalGraphDoesNotDependOnTheOrderOfConstruction) {
  using symbolic::Graph;
  using symbolic::NodeId;
  using symbolic::Op;
  const auto build = [](bool left_first) {
    Graph g;
    const NodeId a = g.input("a", 1), b = g.input("b", 1), c = g.input("c", 1), d = g.input("d", 1);
    NodeId ab, cd;
    if (left_first) {
      ab = g.make(Op::mul, a, b);
      cd = g.make(Op::mul, c, d);
    } else {
      cd = g.make(Op::mul, d, c);
      ab = g.make(Op::mul, b, a);
    }
    // Both operands negated: which folding rule of a + b fires depends on the operand order.
    const NodeId sum = g.make(Op::add, g.make(Op::neg, ab), g.make(Op::neg, cd));
    std::vector<NodeId> roots{g.make(Op::select_greater, sum, ab, cd, sum)};
    return std::make_pair(g.canonical(roots), roots);
  };
  const auto [first, first_roots] = build(true);
  const auto [second, second_roots] = build(false);
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(first_roots, second_roots);
  for (NodeId id = 0; id < first.size(); ++id) {
    const symbolic::Node &x = first.node(id), &y = second.node(id);
    EXPECT_EQ(x.op, y.op) << "node " << id;
    EXPECT_EQ(x.args, y.args) << "node " << id;
    EXPECT_EQ(x.input, y.input) << "node " << id;
  }
}

}  // namespace
}  // namespace sweepgen
