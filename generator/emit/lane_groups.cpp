#include "emit/lane_groups.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

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
    index_users();
    for (const LaneGroup& group : result_.groups) activate_users(group);
    // Bottom-up to a fixed point: a node's lanes are often computed before the other lanes'
    // operands are grouped (the sweeps trace one direction's expression after another). Rounds of
    // complete groups until none forms, then the partial ones, again until neither forms.
    do {
      while (!active_.empty()) round();
    } while (form_partial_groups());
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
    if (!users_.empty()) activate_users(group);
    result_.groups.push_back(std::move(group));
  }

  // Per node of the function, the positions in `computed` of the nodes that a pass may group
  // with it as an operand (groupable, outside the if/else blocks).
  void index_users() {
    for (std::size_t i = 0; i < f_.computed.size(); ++i) {
      position_.emplace(f_.computed[i], i);
      const Node& n = graph_.node(f_.computed[i]);
      if (f_.path_block[i] != 0 || !groupable(n.op)) continue;
      for (int k = 0; k < symbolic::arity(n.op); ++k) users_[n.args[k]].push_back(i);
    }
  }

  // Only a node with an operand in a group has a shape (shapes_of): a pass visits those alone,
  // in the order of `computed`, which gives the groups a visit of every node would.
  void activate_users(const LaneGroup& group) {
    for (NodeId m : group.members) {
      if (m == kNoLane) continue;
      if (const auto found = users_.find(m); found != users_.end()) active_.insert(found->second.begin(), found->second.end());
    }
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

  // The groups' rule, as passes over every node in the order of `computed` would apply it. A pass
  // visits each node that has a shape (an operand in a group) and fills, per shape, its lane of
  // the candidate group of that shape; the node that fills the last lane forms it (a complete
  // group) unless a member was grouped meanwhile; a grouped node fills no more shapes. One shape
  // and lane is one node (the operands are fixed by it, and the graph holds each expression once),
  // so the lanes each shape has, `slots_`, are kept across passes. A pass differs from the one
  // before only where a node got a shape (an operand was grouped): those nodes are visited (the
  // ones behind the node that grouped their operand in the next pass, as a pass would); a shape
  // they fill forms where its last member stands, which is visited too.
  void round() {
    for (std::size_t next = 0;;) {
      const auto at = active_.lower_bound(next);
      if (at == active_.end()) return;
      const std::size_t position = *at;
      next = position + 1;
      active_.erase(at);
      visit(position);
    }
  }

  void visit(std::size_t position) {
    const NodeId id = f_.computed[position];
    if (grouped(id)) return;
    for (Shape key : shapes_of(id)) {
      const std::size_t lane = key.lane, lanes = key.lanes;
      key.lane = 0;
      auto [found, opened] = slots_.try_emplace(key);
      std::vector<NodeId>& members = found->second;
      if (opened) members.assign(lanes, kNoLane);
      if (members[lane] == kNoLane) {
        members[lane] = id;
        touched_.insert(key);
      }
      std::size_t last = 0;
      bool complete = true;
      for (NodeId m : members) {
        if (m == kNoLane || grouped(m)) {
          complete = false;
          break;
        }
        last = std::max(last, position_.at(m));
      }
      if (complete && last == position) form(key, members, true);
      else if (complete) active_.insert(last);  // forms when the pass reaches its last member
      if (grouped(id)) break;
    }
  }

  // Once no complete group forms, a pass forms, in the order the shapes are first met, every
  // candidate whose vectors take fewer instructions on the x86-64 baseline than their members'
  // scalar operations (the lower triangle of E^A_cstr: column k has lanes k + 1..). A shape that
  // gained no member since the last such pass cannot have gained a reason to form: only those are
  // tried. Whether one formed.
  bool form_partial_groups() {
    std::vector<std::pair<std::pair<std::size_t, std::size_t>, Shape>> order;  // (first member, its shape's rank)
    for (const Shape& key : touched_) {
      std::size_t first = kNone;
      for (NodeId m : slots_.at(key))
        if (m != kNoLane && !grouped(m)) first = std::min(first, position_.at(m));
      if (first == kNone) continue;
      std::size_t rank = 0;
      for (Shape shape : shapes_of(f_.computed[first])) {
        shape.lane = 0;
        if (!(shape < key) && !(key < shape)) break;
        ++rank;
      }
      order.push_back({{first, rank}, key});
    }
    touched_.clear();
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    bool formed = false;
    for (const auto& [at, key] : order) formed = form(key, slots_.at(key), false) || formed;
    return formed;
  }

  bool grouped(NodeId id) const { return result_.lane_of.count(id) != 0; }

  // Forms the group of shape `key` from the candidate `members` (those grouped meanwhile left out):
  // a complete one only with every lane, a partial one only where it saves instructions.
  bool form(const Shape& key, const std::vector<NodeId>& members, bool complete) {
    LaneGroup group;
    group.members = members;
    std::size_t present = 0;
    for (std::size_t l = 0; l < members.size(); ++l) {
      if (members[l] != kNoLane && grouped(members[l])) group.members[l] = kNoLane;
      present += group.members[l] != kNoLane ? 1 : 0;
    }
    if (complete ? present < group.members.size() : present <= LaneGroups::baseline_instructions(group)) return false;
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
    return true;
  }

  const symbolic::Trace& trace_;
  const symbolic::Graph& graph_;
  const FunctionPlan& f_;
  LaneGroups result_;
  std::unordered_map<NodeId, std::vector<std::size_t>> users_;
  std::unordered_map<NodeId, std::size_t> position_;  // in `computed`
  std::set<std::size_t> active_;   // positions the current pass (round) still visits
  std::map<Shape, std::vector<NodeId>> slots_;  // per shape (lane 0), the node of each lane met so far
  std::set<Shape> touched_;        // shapes that gained a member since the last partial pass
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
