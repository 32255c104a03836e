// The symbolic trace records exactly the reference sweeps: evaluating the traced graph in
// double reproduces every state field of ReferenceSolver<double>. Folding only applies exact
// identities (x*1, x+0, reordering of commutative operands), so each differing site perturbs one
// intermediate by a rounding or two; downstream such a perturbation is amplified by up to
// κ = max(1, cond_s(E^A_cstr,0), cond(M)): through ν by cond_s(E), through the accelerations of
// a torque (the refinement (R1) feeds Ẍ_tip back into ν, saturate_exact runs forward dynamics
// with its clamped torque) by cond(M). Tolerance: kFoldingRoundings eps κ relative, at least
// 1e-13 (operand orders Eigen may vectorise differently); states with κ > kMaxCondition are
// counted and skipped, so the tolerance never exceeds 64 · 2.2e-16 · 1e8 ≈ 1.4e-6, while a
// flipped sign or a dropped term is O(1).
#include <gtest/gtest.h>

#include <map>
#include <stdexcept>

#include "oracle/condition_number.hpp"
#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "solver/derivative_seeds.hpp"
#include "solver/flat_layout.hpp"
#include "solver/outward_sweep.hpp"
#include "solver/reference_solver.hpp"
#include "solver/state_fields.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"
#include "support/skip_count.hpp"
#include "symbolic/symbol.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using Key = std::tuple<std::string, std::string, int, int>;

constexpr double kFoldingRoundings = 64;
constexpr double kMaxCondition = 1e8;

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
  // Random unit directions make κ > 1e8 now and then (6 random directions on the 6-joint UR5 are often
  // nearly dependent; measured 25 of 240 states, the printed line): a fifth
  // leaves room.
  test::SkipCount skips("trace vs reference, kappa > 1e8", 0.2);
  for (const auto& robot : test::bundled_robots()) {
    const model::Chain chain = test::load_bundled(robot);
    for (std::size_t nc : {0u, 3u, 6u}) {
      SCOPED_TRACE(robot.name + " Nc=" + std::to_string(nc));
      const solver::DriverLayout layout = full_layout(chain, nc);
      symbolic::TraceRequest request{layout, policies, {}, std::numeric_limits<double>::epsilon(), {}};
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

        // The same values, by what each input stands for.
        const std::vector<double> positions = solver::generated_positions(q, spatial::Mat3<double>::Identity(), false);
        const auto value_of = [&](const symbolic::Input& in) {
          const auto component = [&](const spatial::Force<double>& f) {
            return in.index < 3 ? f.moment[in.index] : f.force[in.index - 3];
          };
          switch (in.quantity) {
            case symbolic::Quantity::joint_position:
            case symbolic::Quantity::base_rotation: return positions[in.index];
            case symbolic::Quantity::joint_velocity: return qd[in.index];
            case symbolic::Quantity::feedforward_torque: return d.torques.at(in.instance)[in.index];
            case symbolic::Quantity::external_force: return component(d.external_forces.at(in.instance));
            case symbolic::Quantity::constraint_direction: return component(d.constraint_directions.at(in.instance));
            case symbolic::Quantity::energy_setpoint: return beta[in.index];
          }
          throw std::logic_error("unknown input quantity");
        };
        std::vector<double> inputs;
        for (const auto& in : trace.inputs) inputs.push_back(value_of(in));
        const std::vector<double> values = trace.graph.evaluate(inputs);

        std::map<Key, double> expected;
        const auto keep = [&expected](const std::string& group) {
          return [&expected, group](const std::string& array, int body, int component, double v) {
            expected[{group, array, body, component}] = v;
          };
        };
        reference.outward(q, qd);
        reference.decompose();
        const double condition = std::max(
            {1.0, nc > 0 ? oracle::scaled_condition_number(reference.articulated().body[0].constraint_energy) : 1.0,
             report::inertia_condition_number(chain, q.cast<report::Precise>(), {})});
        if (skips.skip(!(condition <= kMaxCondition), "kappa > 1e8")) continue;
        const double tolerance = std::max(1e-13, kFoldingRoundings * std::numeric_limits<double>::epsilon() * condition);
        solver::visit_fields(reference.kinematics(), keep("kinematics"));
        solver::visit_fields(reference.articulated(), layout, keep("articulated"));
        for (auto policy : policies) solver::visit_fields(reference.solve(policy, beta), policy, keep(solver::name(policy)));

        ASSERT_EQ(expected.size(), trace.fields.size());
        for (const auto& field : trace.fields) {
          const double want = expected.at({field.group, field.array, field.body, field.component});
          const double error = std::abs(values[field.node] - want) / std::max(1.0, std::abs(want));
          worst = std::max(worst, error / tolerance);
          ASSERT_LE(error, tolerance) << field.group << "." << field.array << "[" << field.body << "][" << field.component
                                  << "]: traced " << values[field.node] << ", reference " << want;
        }
      }
    }
  }
  std::cout << "trace vs reference: max relative difference / tolerance " << worst << "\n";
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
    const NodeId a = g.input(), b = g.input(), c = g.input(), d = g.input();
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

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

// A tree pays for constraint sets only along their paths: with a set on the left hand only,
// every unit constraint force and constraint energy on the right arm of the dual Panda is the
// constant 0 in the trace (so the emitted code has none of them), while on the left arm and the
// shared torso they are computed; with sets on both hands both arms carry them.
TEST(Trace, ABranchWithoutConstraintsCarriesNoConstraintTerms) {
  const model::Chain chain =
      test::load_tree("robots/dual_panda/dual_panda.urdf", "station", {"left_panda_hand", "right_panda_hand"});
  const auto is_right_arm = [&](int body) { return body >= 9; };  // right_panda_link1..7
  const auto computed_terms = [&](std::vector<solver::ConstraintSet> sets, bool right) {
    solver::DriverLayout layout;
    layout.torques = {"tau_ff"};
    for (const auto& set : sets) layout.constraints += set.count;
    layout.sets = std::move(sets);
    layout.decompose_all();
    const symbolic::Trace trace = symbolic::trace_solver(
        chain, {layout, {solver::Policy::original}, {}, std::numeric_limits<double>::epsilon(), {}});
    int terms = 0;
    for (const auto& f : trace.fields)
      if ((f.array == "constraint_force" || f.array == "constraint_energy") && f.body > 0 && is_right_arm(f.body) == right &&
          trace.graph.node(f.node).op != symbolic::Op::constant)
        ++terms;
    return terms;
  };
  EXPECT_EQ(computed_terms({solver::ConstraintSet::on("left_panda_hand", 6)}, true), 0) << "the right arm computes constraint terms";
  EXPECT_GT(computed_terms({solver::ConstraintSet::on("left_panda_hand", 6)}, false), 0);
  EXPECT_GT(computed_terms({solver::ConstraintSet::on("left_panda_hand", 6), solver::ConstraintSet::on("right_panda_hand", 6)},
                           true),
            0);
}

// Finer: each direction only along its own path. On the quadruped (four feet, fixed directions) and
// the dual Panda (two hands, run-time directions), in the columns (I2) and in the rows (I6), every
// quantity of direction k on a body that does not carry k's set (a body on another leg or arm: k's
// link is neither on it nor beyond it) is the constant 0 in the trace, so nothing of a foot's
// constraint is propagated through the other legs: the unit-force column (I2), the row r_i,k, the
// acceleration energy (I5) and every entry (k, l) of the constraint-space matrix (I3).
TEST(Trace, ADirectionReachesOnlyTheJointsThatMoveItsLink) {
  for (const char* path : {"robots/quadruped/quadruped_stance.yaml", "robots/dual_panda/dual_panda_box.yaml"})
    for (const auto rows : {solver::ConstraintRows::inward_columns, solver::ConstraintRows::outward_rows}) {
      const scene::Scene s = scene::load_scene(std::string(SWEEPGEN_SOURCE_DIR) + "/" + path);
      const model::Chain chain = scene::load_scene_chain(s);
      solver::SolverOptions options = s.solver_options();
      options.constraint_rows = rows;
      const symbolic::Trace trace =
          symbolic::trace_solver(chain, {s.layout, s.policies, options, std::numeric_limits<double>::epsilon(), {}});
      const solver::SolverModel<double> model(chain, s.layout, options, std::numeric_limits<double>::epsilon());
      const int nc = static_cast<int>(model.constraints());
      // Whether body b carries direction k's set (the base, body 0, carries every set).
      const auto carries = [&](int b, int k) { return model::supports(chain.parent, b, model.set_of(k).body); };
      int zeros = 0, computed = 0;
      for (const auto& f : trace.fields) {
        if (f.group != "articulated" || f.body <= 0) continue;
        bool outside;
        if (f.array == "constraint_force") outside = !carries(f.body, f.component / 6);
        else if (f.array == "constraint_row" || f.array.rfind("acceleration_energy_", 0) == 0) outside = !carries(f.body, f.component);
        else if (f.array == "constraint_energy") outside = !carries(f.body, f.component / nc) || !carries(f.body, f.component % nc);
        else continue;
        const bool constant_zero = trace.graph.is_constant(f.node, 0);
        if (outside) {
          EXPECT_TRUE(constant_zero) << path << ": " << f.array << " of body " << f.body << ", entry " << f.component;
        }
        zeros += outside;
        computed += !constant_zero;
      }
      EXPECT_GT(zeros, 0) << path;
      EXPECT_GT(computed, 0) << path;
    }
}

// Tree sparsity of the derivatives (D1, D2): body i's velocity and bias force do not depend on
// q_j or q̇_j of a joint j outboard of it, and the dual scalar over Symbol folds those tangents to
// the constant 0 (x·0 = 0, x + 0 = x), so the derivative functions compute none of them; the
// tangents along body i's own joint are computed.
TEST(Trace, TangentsAlongOutboardJointsFoldToZero) {
  using D = solver::Dual<symbolic::Symbol>;
  const model::Chain chain = test::load_bundled(test::bundled_robots().front());
  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  layout.decompose_all();
  symbolic::Graph graph;
  symbolic::TraceScope scope(graph);
  const solver::SolverModel<D> model(chain, layout, {}, std::numeric_limits<double>::epsilon());
  const std::size_t n = model.dof();
  const solver::DerivativeColumns columns{n, 0, {}};
  solver::JointVector<D> q(n), qd(n);
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = solver::seeded(symbolic::Symbol::from_node(graph.input()), columns.q(i), columns);
    qd[i] = solver::seeded(symbolic::Symbol::from_node(graph.input()), columns.qd(i), columns);
  }
  auto kin = solver::KinematicsState<D>::sized(n);
  solver::outward_sweep_base_to_tip(model, q, qd, kin);
  int outboard_computed = 0, own_computed = 0;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= n; ++j)
      for (const D* x : {&kin.body[i].velocity.angular[0], &kin.body[i].velocity.linear[0],
                         &kin.body[i].bias_force.moment[0], &kin.body[i].bias_force.force[0]})
        for (int c = 0; c < 3; ++c)
          for (const std::size_t column : {columns.q(j - 1), columns.qd(j - 1)}) {
            const bool computed = !graph.is_constant(x[c].derivative(column).id(), 0);
            if (j > i) outboard_computed += computed;
            if (j == i) own_computed += computed;
          }
  EXPECT_EQ(outboard_computed, 0) << "tangents along joints outboard of a body are computed";
  EXPECT_GT(own_computed, 0);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
