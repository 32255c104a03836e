#include "emit/lane_groups.hpp"

#include <algorithm>
#include <array>
#include <optional>

namespace sweepgen::emit {
namespace {

using symbolic::Node;
using symbolic::Op;
using symbolic::Quantity;

constexpr std::size_t kNone = ~std::size_t(0);

bool groupable(Op op) { return op == Op::add || op == Op::sub || op == Op::mul || op == Op::div || op == Op::neg; }
bool commutative(Op op) { return op == Op::add || op == Op::mul; }

// A node's shape with respect to the groups: its operation and, per operand, the operand itself
// (shared by every lane) or the group it is a lane of; and that lane.
struct Shape {
  std::array<std::int64_t, 3> key{};  // op; operands: id >= 0 shared, -(group + 1) a lane of `group`
  std::size_t lane = kNone;
  std::size_t lanes = 0;  // members of the groups read
  bool operator<(const Shape& o) const { return key < o.key; }
};

class Finder {
 public:
  Finder(const symbolic::Trace& trace, const FunctionPlan& f) : trace_(trace), graph_(trace.graph), f_(f) {}

  LaneGroups find() {
    if (trace_.constraint_rows != solver::ConstraintRows::inward_columns) return result_;
    seed();
    if (result_.groups.empty()) return result_;
    // Bottom-up to a fixed point: a node's lanes are often computed before the other lanes'
    // operands are grouped (the sweeps trace one direction's expression after another).
    for (bool partial = false;;) {
      if (pass(partial)) {
        partial = false;
      } else if (!partial) {
        partial = true;
      } else {
        break;
      }
    }
    return result_;
  }

 private:
  // Group j of set s: α_k,j for the run-time directions k of s (at least two), lane k − first.
  void seed() {
    std::map<std::pair<std::size_t, std::uint32_t>, NodeId> alpha;  // (run-time direction, component)
    for (NodeId id : f_.leaves) {
      const Node& n = graph_.node(id);
      if (n.op != Op::input) continue;
      const symbolic::Input& input = trace_.inputs[n.input];
      if (input.quantity == Quantity::constraint_direction) alpha[{input.instance, input.index}] = id;
    }
    std::size_t first = 0;
    for (const auto& set : trace_.layout.constraint_sets()) {
      if (set.directions_fixed()) continue;
      for (std::uint32_t j = 0; set.count >= 2 && j < 6; ++j) {
        LaneGroup group;
        group.seed = true;
        for (std::size_t k = first; k < first + set.count; ++k) {
          const auto found = alpha.find({k, j});
          if (found == alpha.end()) break;
          group.members.push_back(found->second);
        }
        if (group.members.size() == set.count) add(std::move(group));
      }
      first += set.count;
    }
  }

  void add(LaneGroup group) {
    const std::size_t g = result_.groups.size();
    for (std::size_t l = 0; l < group.members.size(); ++l)
      if (group.members[l] != kNoLane) result_.lane_of[group.members[l]] = {g, l};
    result_.groups.push_back(std::move(group));
  }

  // The shapes node `id` can take: each laned operand either read in the node's lane or, where
  // its lane differs, broadcast (an entry of E^A_cstr, r_l D^-1 r_k, is lane l of column k).
  std::vector<Shape> shapes_of(NodeId id) const {
    const Node& n = graph_.node(id);
    if (!groupable(n.op)) return {};
    const int operands = symbolic::arity(n.op);
    std::array<const std::pair<std::size_t, std::size_t>*, 2> laned{};
    for (int k = 0; k < operands; ++k) {
      const auto found = result_.lane_of.find(n.args[k]);
      if (found != result_.lane_of.end()) laned[k] = &found->second;
    }
    std::vector<Shape> shapes;
    for (int broadcast = 0; broadcast < (1 << operands); ++broadcast) {  // bit k: operand k broadcast
      Shape shape;
      shape.key[0] = static_cast<std::int64_t>(n.op);
      bool valid = true;
      for (int k = 0; k < operands && valid; ++k) {
        const bool lane_read = laned[k] != nullptr && !(broadcast & (1 << k));
        if (!lane_read) {
          if (broadcast & (1 << k) && laned[k] == nullptr) valid = false;  // only a lane is broadcast
          shape.key[1 + k] = n.args[k];
          continue;
        }
        const auto [group, lane] = *laned[k];
        const std::size_t lanes = result_.groups[group].members.size();
        valid = !(n.op == Op::div && k == 1) &&  // never divide by a lane (a partial group's empty lanes)
                (shape.lane == kNone || shape.lane == lane) && (shape.lanes == 0 || shape.lanes == lanes);
        shape.lane = lane;
        shape.lanes = lanes;
        shape.key[1 + k] = -static_cast<std::int64_t>(group) - 1;
      }
      if (!valid || shape.lane == kNone) continue;
      if (commutative(n.op) && shape.key[1] > shape.key[2]) std::swap(shape.key[1], shape.key[2]);
      shapes.push_back(shape);
    }
    return shapes;
  }

  // One pass over the function's nodes; whether a group formed. Without `partial`, only groups
  // with a member in every lane form; with it, once no more complete group can form, also those
  // (the lower triangle of E^A_cstr: column k has lanes k + 1..) whose vectors take fewer
  // instructions on the x86-64 baseline than their members' scalar operations.
  bool pass(bool partial) {
    struct Candidate {
      std::vector<NodeId> members;
      std::size_t filled = 0;
      bool closed = false;  // a complete group of this shape formed in this pass
    };
    std::map<Shape, Candidate> candidates;
    std::vector<Shape> order;  // candidates in the order they were opened
    bool grew = false;
    const auto form = [&](const Shape& key, Candidate& c, bool complete) {
      LaneGroup group;
      group.members = c.members;
      std::size_t present = 0;
      for (std::size_t l = 0; l < c.members.size(); ++l) {
        if (c.members[l] != kNoLane && result_.lane_of.count(c.members[l])) group.members[l] = kNoLane;
        present += group.members[l] != kNoLane ? 1 : 0;
      }
      if (complete ? present < group.members.size() : present <= LaneGroups::baseline_instructions(group)) return;
      const std::size_t lane = std::find_if(group.members.begin(), group.members.end(), [](NodeId m) { return m != kNoLane; }) -
                               group.members.begin();
      const Node& n = graph_.node(group.members[lane]);
      for (int k = 0; k < symbolic::arity(n.op); ++k) {
        const auto found = result_.lane_of.find(n.args[k]);
        const std::int64_t as_group = found == result_.lane_of.end() ? 0 : -static_cast<std::int64_t>(found->second.first) - 1;
        group.lane_operand[k] = found != result_.lane_of.end() && found->second.second == lane &&
                                (key.key[1] == as_group || key.key[2] == as_group);
      }
      add(std::move(group));
      grew = true;
    };
    for (std::size_t i = 0; i < f_.computed.size(); ++i) {
      const NodeId id = f_.computed[i];
      if (f_.path_block[i] != 0 || result_.lane_of.count(id)) continue;
      for (Shape key : shapes_of(id)) {
        const std::size_t lane = key.lane, lanes = key.lanes;
        key.lane = 0;
        auto [found, opened] = candidates.try_emplace(key);
        Candidate& c = found->second;
        if (opened) {
          order.push_back(key);
          c.members.assign(lanes, kNoLane);
        }
        if (c.closed || c.members[lane] != kNoLane) continue;
        c.members[lane] = id;
        if (++c.filled == c.members.size()) {
          form(key, c, true);
          c.closed = true;
        }
        if (result_.lane_of.count(id)) break;
      }
    }
    if (partial)
      for (const Shape& key : order) {
        Candidate& c = candidates.at(key);
        if (!c.closed) form(key, c, false);
      }
    return grew;
  }

  const symbolic::Trace& trace_;
  const symbolic::Graph& graph_;
  const FunctionPlan& f_;
  LaneGroups result_;
};

}  // namespace

std::vector<LaneGroups::Chunk> LaneGroups::chunks(std::size_t lanes) {
  std::vector<Chunk> result;
  for (std::size_t first = 0; first < lanes; first += kWidth) result.push_back({first, std::min(kWidth, lanes - first)});
  return result;
}

std::size_t LaneGroups::baseline_instructions(const LaneGroup& group) {
  std::size_t instructions = 0;
  for (const Chunk& c : chunks(group.members.size()))
    if (std::any_of(group.members.begin() + c.first, group.members.begin() + c.first + c.count,
                    [](NodeId m) { return m != kNoLane; }))
      ++instructions;
  return instructions;
}

std::size_t LaneGroups::operations_saved() const {
  std::size_t saved = 0;
  for (const LaneGroup& group : groups) {
    if (group.seed) continue;
    const auto present =
        static_cast<std::size_t>(std::count_if(group.members.begin(), group.members.end(), [](NodeId m) { return m != kNoLane; }));
    saved += present - baseline_instructions(group);
  }
  return saved;
}

LaneGroups find_lane_groups(const symbolic::Trace& trace, const FunctionPlan& function) {
  return Finder(trace, function).find();
}

}  // namespace sweepgen::emit
