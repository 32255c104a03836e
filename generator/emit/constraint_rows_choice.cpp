#include "emit/constraint_rows_choice.hpp"

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "emit/lane_groups.hpp"
#include "emit/op_count.hpp"
#include "solver/constraint_row_steps.hpp"

namespace sweepgen::emit {
namespace {

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

}  // namespace

ChosenRows choose_constraint_rows(const model::Chain& chain, const EmitRequest& request,
                                  symbolic::TraceRequest trace_request) {
  const std::size_t nc = request.trace.layout.constraints;
  std::vector<solver::ConstraintRows> candidates{solver::ConstraintRows::inward_columns};
  const solver::ConstraintRowSteps steps = solver::constraint_row_steps(chain, request.trace.layout);
  const bool rows_too_long = steps.outward_rows > kRowStepsTraced * steps.inward_columns;
  if (request.constraint_rows) candidates = {*request.constraint_rows};
  else if (nc > 0 && !request.expose_all && !rows_too_long)
    candidates.push_back(solver::ConstraintRows::outward_rows);
  std::optional<ChosenRows> best;
  std::map<solver::ConstraintRows, PlannedCost> counted;
  for (const solver::ConstraintRows rows : candidates) {
    trace_request.options.constraint_rows = rows;
    symbolic::Trace candidate = symbolic::trace_solver(chain, trace_request);
    Plan candidate_plan = make_plan(candidate, request.expose_all);
    counted[rows] = planned_cost(candidate, candidate_plan);
    const solver::ConstraintRows kept = best ? best->trace.constraint_rows : rows;
    if (!best || rows_cost(rows, counted[rows], nc) < rows_cost(kept, counted[kept], nc))
      best = ChosenRows{std::move(candidate), std::move(candidate_plan), ""};
  }
  if (nc > 0)
    best->note = rows_note(best->trace.constraint_rows, candidates.size() > 1 ? counted : decltype(counted){},
                           request.constraint_rows.has_value(), request.expose_all, nc, rows_too_long ? &steps : nullptr);
  return std::move(*best);
}

}  // namespace sweepgen::emit
