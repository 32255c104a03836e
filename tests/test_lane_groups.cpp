// SIMD over the constraint directions (emit/lane_groups.hpp): the lanes of each group compute
// exactly what its members compute, the generator weighs them when it picks (I2) or (I6), and the
// portable fallback (an array with the same operators) gives the vector code's numbers bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "emit/lane_groups.hpp"
#include "emit/solver_emitter.hpp"
#include "report/compiled_solver.hpp"
#include "report/measure.hpp"
#include "support/bundled_robots.hpp"
#include "support/compiled_scene.hpp"
#include "support/random_chain.hpp"
#include "support/same_bits.hpp"
#include "support/temp_dir.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using emit::kNoLane;
using emit::LaneGroups;
using symbolic::NodeId;

symbolic::TraceRequest lanes_request(solver::DriverLayout layout, solver::ConstraintRows rows) {
  symbolic::TraceRequest r;
  r.layout = std::move(layout);
  r.layout.torques = {"tau_ff"};
  r.layout.decompose_all();
  r.policies = {solver::Policy::original, solver::Policy::prioritize_external};
  r.options.constraint_rows = rows;
  r.epsilon = std::numeric_limits<double>::epsilon();
  return r;
}

solver::DriverLayout directions_at_tip(std::size_t nc) {
  solver::DriverLayout layout;
  layout.constraints = nc;
  return layout;
}

// Two sets of run-time directions on two links (a tree's two tips where it has them).
solver::DriverLayout two_sets(const std::string& a, const std::string& b, std::size_t count) {
  solver::DriverLayout layout;
  layout.sets = {solver::ConstraintSet::on(a, count), solver::ConstraintSet::on(b, count)};
  layout.constraints = 2 * count;
  return layout;
}

struct Checked {
  std::size_t groups = 0, partial = 0, broadcast_lanes = 0;
};

// The invariant the writer relies on: in each group, every member has the first member's operation,
// and per operand either reads its own lane of one and the same group, or is the very node the
// first member reads (shared or one lane broadcast); a partial group has more members than its
// vectors take instructions on the baseline; no member is in two groups.
Checked check_groups(const symbolic::Trace& trace, const emit::FunctionPlan& f, const LaneGroups& lanes) {
  Checked checked;
  const auto& g = trace.graph;
  std::size_t members = 0;
  for (std::size_t gi = 0; gi < lanes.groups.size(); ++gi) {
    const emit::LaneGroup& group = lanes.groups[gi];
    std::size_t present = 0;
    NodeId first = kNoLane;
    for (std::size_t l = 0; l < group.members.size(); ++l) {
      const NodeId m = group.members[l];
      if (m == kNoLane) continue;
      ++present;
      EXPECT_EQ(lanes.lane_of.at(m), std::make_pair(gi, l)) << f.name << " group " << gi;
      if (group.seed) {
        EXPECT_EQ(g.node(m).op, symbolic::Op::input);
        continue;
      }
      if (first == kNoLane) first = m;
      const auto& n = g.node(m);
      const auto& n0 = g.node(first);
      EXPECT_EQ(n.op, n0.op) << f.name << " group " << gi << " lane " << l;
      if (n.op != n0.op) continue;
      // Each operand as the vector expression reads it: -(group + 1) for its own lane of a group
      // the first member reads lane by lane, else the node itself (the same in every lane).
      std::vector<std::int64_t> expected, read;
      for (int k = 0; k < symbolic::arity(n.op); ++k)
        expected.push_back(group.lane_operand[k] ? -static_cast<std::int64_t>(lanes.lane_of.at(n0.args[k]).first) - 1
                                                 : static_cast<std::int64_t>(n0.args[k]));
      for (int k = 0; k < symbolic::arity(n.op); ++k) {
        const auto found = lanes.lane_of.find(n.args[k]);
        const std::int64_t as_lane = found == lanes.lane_of.end() || found->second.second != l
                                         ? 0
                                         : -static_cast<std::int64_t>(found->second.first) - 1;
        const bool lane_read = as_lane != 0 && std::count(expected.begin(), expected.end(), as_lane) > 0;
        read.push_back(lane_read ? as_lane : static_cast<std::int64_t>(n.args[k]));
        if (!lane_read) checked.broadcast_lanes += found != lanes.lane_of.end() ? 1 : 0;
      }
      // + and × operands are ordered by their shape, which differs between lanes: any order.
      if (n.op == symbolic::Op::add || n.op == symbolic::Op::mul) {
        std::sort(expected.begin(), expected.end());
        std::sort(read.begin(), read.end());
      }
      EXPECT_EQ(read, expected) << f.name << " group " << gi << " lane " << l;
    }
    members += present;
    if (present < group.members.size()) {
      ++checked.partial;
      EXPECT_GT(present, LaneGroups::baseline_instructions(group)) << f.name << " group " << gi;
    }
    checked.groups += group.seed ? 0 : 1;
  }
  EXPECT_EQ(members, lanes.lane_of.size()) << f.name << ": a node in two groups";
  return checked;
}

Checked check_scene(const model::Chain& chain, const symbolic::TraceRequest& r) {
  const symbolic::Trace trace = symbolic::trace_solver(chain, r);
  const emit::Plan plan = emit::make_plan(trace, false);
  Checked total;
  for (const auto& f : plan.functions) {
    const Checked c = check_groups(trace, f, emit::find_lane_groups(trace, f));
    total.groups += c.groups;
    total.partial += c.partial;
    total.broadcast_lanes += c.broadcast_lanes;
  }
  return total;
}

TEST(LaneGroups, EveryLaneComputesItsMembersExpression) {
  const model::Chain panda = test::load_bundled(test::bundled_robots().front());
  const auto columns = solver::ConstraintRows::inward_columns;
  for (std::size_t nc : {2u, 3u, 6u}) {
    const Checked c = check_scene(panda, lanes_request(directions_at_tip(nc), columns));
    EXPECT_GT(c.groups, 50u) << "Nc=" << nc;
    // E^A_cstr's lower triangle: column k of six directions has lanes k + 1.., read as lane l
    // of r times lane k of D^-1 r broadcast.
    if (nc == 6) {
      EXPECT_GT(c.partial, 0u);
      EXPECT_GT(c.broadcast_lanes, 0u);
    }
  }
  const model::Chain tree = test::RandomChainGenerator(71).tree(7);
  ASSERT_FALSE(tree.branch_tips.empty());
  const Checked c = check_scene(tree, lanes_request(two_sets(tree.tip_link, tree.branch_tips.front(), 3), columns));
  EXPECT_GT(c.groups, 20u);
}

// Lanes are for the columns of run-time directions: fixed directions are folded into the
// constants (no two columns alike) and the rows (I6) take α only at their end.
TEST(LaneGroups, FixedDirectionsAndOutwardRowsHaveNoLanes) {
  const model::Chain panda = test::load_bundled(test::bundled_robots().front());
  solver::DriverLayout fixed = directions_at_tip(3);
  fixed.sets = {solver::ConstraintSet::on("", 3, {spatial::Force<double>{{0, 0, 0}, {1, 0, 0}},
                                                 spatial::Force<double>{{0, 0, 0}, {0, 1, 0}},
                                                 spatial::Force<double>{{0, 0, 0}, {0, 0, 1}}})};
  EXPECT_EQ(check_scene(panda, lanes_request(fixed, solver::ConstraintRows::inward_columns)).groups, 0u);
  EXPECT_EQ(check_scene(panda, lanes_request(directions_at_tip(6), solver::ConstraintRows::outward_rows)).groups, 0u);
  EXPECT_EQ(check_scene(panda, lanes_request(directions_at_tip(1), solver::ConstraintRows::inward_columns)).groups, 0u);
}

// The vector extension and the array fallback (SWEEPGEN_SCALAR_LANES, or a compiler without the
// extension) compute each lane with the same operations in the same order: on the x86-64
// baseline (SSE2, no FMA to contract into) every output, status words included, of 200 states
// must agree bit for bit, double and float.
TEST(LaneGroups, ScalarFallbackAgreesBitForBit) {
  const model::Chain chain = test::RandomChainGenerator(73).chain(5);
  scene::Scene s;
  s.solver = "lanes_fallback";
  s.chain.urdf = chain.source;
  s.layout = directions_at_tip(3);
  s.layout.torques = {"tau_ff"};
  s.layout.decompose_all();
  s = report::report_scene(std::move(s));
  test::TempDir vector_dir, scalar_dir;
  const report::CompiledSolver vectors = test::compile_scene(s, chain, vector_dir.path(), report::Optimisation::deployed);
  {
    std::ifstream source(vector_dir.path() / "lanes_fallback.cpp");
    const std::string text((std::istreambuf_iterator<char>(source)), std::istreambuf_iterator<char>());
    ASSERT_NE(text.find("  Lanes2 lanes"), std::string::npos) << "no lanes to compare";
    // A batch's group is LaneArray<Batch>, an aggregate: declared const, GCC's scalar replacement
    // passes it over and, where dead-store elimination gives up in a long function, each stays in a
    // stack slot of its own (Baxter's batch decompose: a 136 KiB frame, batch 1.29x the flat loop
    // instead of 2.33x; bench/README.md, "Lane groups in batches").
    EXPECT_EQ(text.find("const Lanes2 "), std::string::npos) << "a lane group declared const";
  }
  const std::filesystem::path compiler = scalar_dir.path() / "cxx-scalar-lanes";
  {
    std::ofstream script(compiler);
    script << "#!/bin/sh\nexec c++ -DSWEEPGEN_SCALAR_LANES \"$@\"\n";
  }
  std::filesystem::permissions(compiler, std::filesystem::perms::owner_all);
  const report::CompileProgress quiet{[](int, const std::string&) {}, [](const std::string&) {}};
  const report::CompiledSolver scalars = report::compile_scene_solver(s, chain, scalar_dir.path(), compiler.string(), quiet);
  ASSERT_NE(vectors.command, scalars.command);

  const std::size_t out_size = s.flat_layout(chain).out_size();
  using test::flat_output;
  using test::same_bits;
  std::size_t differing = 0;
  const auto problems = report::random_problems(s, chain, 200, 37);
  for (const report::Problem& p : problems) {
    const std::vector<float> in_f32(p.flat.begin(), p.flat.end());
    differing += !same_bits(flat_output(vectors.solve_f64_of.at(solver::Policy::original), p.flat, out_size),
                            flat_output(scalars.solve_f64_of.at(solver::Policy::original), p.flat, out_size));
    differing += !same_bits(flat_output(vectors.solve_f32, in_f32, out_size), flat_output(scalars.solve_f32, in_f32, out_size));
  }
  EXPECT_EQ(differing, 0u) << "of " << 2 * problems.size() << " outputs";
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
