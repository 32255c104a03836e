// SIMD over the constraint directions: which nodes of one generated function are the
// same expression once per run-time direction α_k of a constraint set, so that the writer computes
// them together, one lane per direction, in one vector expression.
//
// A set's directions are treated alike by every equation that carries them: the unit forces
// F^A_cstr,i (I2) are X^T P^T applied to each α_k, so the trace holds, per direction, isomorphic
// expressions that share every operand except the direction's own. Only the columns (I2) get
// lanes: the rows (I6) take α_k at their end, where each lane would be read out at once for
// E^A_cstr's entries (measured slower: bench/README.md, "Two lanes over the constraint columns"). Grouping is bottom-up (as a compiler's SLP vectoriser, on the traced
// graph): the seeds are the components of the set's α_k (group j holds α_k,j for every k of the
// set, lane k); a node joins lane l of a new group when, for every lane, a node of the same
// operation exists whose operands are either the same node in every lane (a shared value,
// broadcast) or lane l of one group. Only +, −, ×, ÷ and negation are grouped.
// A group is written as vectors of two lanes (chunks of 16 bytes of doubles: one SSE2 register,
// the x86-64 baseline's; wider vectors need 32- or 64-byte stack slots, which the baseline gets
// only by realigning the frame at run time, and measured slower there: bench/README.md, "Two
// lanes over the constraint columns"). A set of odd count pads its last chunk with a copy of that chunk's first
// lane: it computes what that lane computes, so it raises no floating-point exception it does not.
// The writer computes a group where its first member (in FunctionPlan::computed) stands: every
// operand of every member is ready there, a shared one being that member's operand too, a lane
// read being a member of a group with a member earlier still, so written earlier.
#pragma once

#include <array>
#include <unordered_map>
#include <utility>
#include <vector>

#include "emit/function_plan.hpp"

namespace sweepgen::emit {

constexpr NodeId kNoLane = ~NodeId(0);

struct LaneGroup {
  std::vector<NodeId> members;  // per lane: the node of direction first + l, or kNoLane
  bool seed = false;            // the components of the directions, read from the inputs
  // Per operand of the members: read lane by lane (from the operand's group) or, if not, the
  // same node in every lane (a shared value, or one lane of a group, broadcast).
  std::array<bool, 2> lane_operand{};
};

struct LaneGroups {
  std::vector<LaneGroup> groups;
  std::unordered_map<NodeId, std::pair<std::size_t, std::size_t>> lane_of;  // node -> (group, lane)

  // The vectors a group of `lanes` lanes is written as: lanes [first, first + count) in one of
  // kWidth lanes.
  static constexpr std::size_t kWidth = 2;
  struct Chunk {
    std::size_t first, count;
  };
  static std::vector<Chunk> chunks(std::size_t lanes);
  // The vectors a group computes: one instruction each on the baseline (SSE2 does two doubles),
  // one per chunk that holds a member (an empty chunk is not computed).
  static std::size_t baseline_instructions(const LaneGroup& group);
  // Operations the groups save on the baseline: their members less baseline_instructions (the
  // generator's cost model).
  std::size_t operations_saved() const;
};

// The groups of `function` (empty without a set of at least two run-time directions among its
// inputs). Nodes inside an if/else of a path condition (FunctionPlan::path_block) are not grouped.
LaneGroups find_lane_groups(const symbolic::Trace& trace, const FunctionPlan& function);

}  // namespace sweepgen::emit
