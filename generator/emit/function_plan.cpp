#include "emit/function_plan.hpp"

#include "emit/names.hpp"

#include <algorithm>
#include <array>
#include <iterator>
#include <stdexcept>
#include <set>
#include <unordered_map>

namespace sweepgen::emit {
namespace {

using symbolic::Graph;
using symbolic::Node;
using symbolic::Op;

std::vector<int> node_stages(const symbolic::Trace& trace) {
  const Graph& graph = trace.graph;
  std::vector<int> stage(graph.size(), 0);
  for (NodeId id = 0; id < graph.size(); ++id) {
    const Node& n = graph.node(id);
    if (n.op == Op::input) stage[id] = symbolic::stage_of(trace.inputs[n.input].quantity);
    for (int k = 0; k < symbolic::arity(n.op); ++k) stage[id] = std::max(stage[id], stage[n.args[k]]);
  }
  return stage;
}

bool is_leaf_here(const Graph& graph, const std::vector<int>& stage, NodeId id, int function_stage) {
  return graph.node(id).op == Op::input || stage[id] < function_stage;
}

// Reorders `computed` (a topological order) to shorten live ranges, within each block (the
// nodes one anchor field pulled in: banners and the sweep order stay as they are): a bottom-up
// list schedule that places next (i.e. earlier in the code) the ready node (all its users
// placed) that adds the fewest new live values (its operands not yet live) minus the one it
// ends (itself, if live); ties keep the depth-first order. Only the order changes, not what
// is computed: callgrind on panda_nc6 (bench/README.md, "Instructions per operation") counts ~1 % fewer instructions.
void reduce_live_ranges(const Graph& graph, std::vector<NodeId>& computed, const std::vector<int>& blocks) {
  const std::size_t count = computed.size();
  std::unordered_map<NodeId, std::size_t> index;
  for (std::size_t i = 0; i < count; ++i) index.emplace(computed[i], i);
  std::vector<std::vector<std::size_t>> operands(count);
  std::vector<int> users(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const Node& n = graph.node(computed[i]);
    for (int k = 0; k < symbolic::arity(n.op); ++k) {
      const auto found = index.find(n.args[k]);
      if (found == index.end()) continue;
      if (std::find(operands[i].begin(), operands[i].end(), found->second) != operands[i].end()) continue;
      operands[i].push_back(found->second);
      ++users[found->second];
    }
  }
  // The ready nodes of each block by their delta (-1 .. 4: an operation has at most four
  // operands), each bucket in index order. A ready node's delta only falls: its own liveness is
  // settled once it is ready (all its users are placed), and an operand, once live, stays live
  // until it is placed, which is after this node. So each operand that turns live moves its ready
  // users down one bucket: time O(edges log n), not the ready nodes per step.
  constexpr int kLowest = -1, kBuckets = 6;
  std::vector<bool> live(count, false);
  std::vector<int> delta(count, 0);
  std::vector<std::vector<std::size_t>> users_of(count);
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t o : operands[i]) users_of[o].push_back(i);
  std::vector<bool> ready(count, false);
  std::vector<std::array<std::set<std::size_t>, kBuckets>> ready_in_block(blocks.empty() ? 0 : blocks.back() + 1);
  const auto make_ready = [&](std::size_t i) {
    delta[i] = live[i] ? -1 : 0;
    for (std::size_t o : operands[i]) delta[i] += live[o] ? 0 : 1;
    ready[i] = true;
    ready_in_block[blocks[i]][delta[i] - kLowest].insert(i);
  };
  for (std::size_t i = 0; i < count; ++i)
    if (users[i] == 0) make_ready(i);
  std::vector<std::size_t> order;
  order.reserve(count);
  for (int b = static_cast<int>(ready_in_block.size()) - 1; b >= 0; --b) {
    auto& buckets = ready_in_block[b];
    for (;;) {
      auto bucket = std::find_if(buckets.begin(), buckets.end(), [](const auto& set) { return !set.empty(); });
      if (bucket == buckets.end()) break;
      const std::size_t best = *bucket->rbegin();  // ties: the last in depth-first order
      bucket->erase(std::prev(bucket->end()));
      ready[best] = false;
      live[best] = false;
      order.push_back(best);
      for (std::size_t o : operands[best]) {
        if (!live[o]) {
          live[o] = true;
          for (std::size_t u : users_of[o]) {
            if (!ready[u]) continue;
            auto& sets = ready_in_block[blocks[u]];
            sets[delta[u] - kLowest].erase(u);
            sets[--delta[u] - kLowest].insert(u);
          }
        }
        if (--users[o] == 0) make_ready(o);
      }
    }
  }
  std::vector<NodeId> result;
  result.reserve(count);
  for (auto it = order.rbegin(); it != order.rend(); ++it) result.push_back(computed[*it]);
  computed = std::move(result);
}

// Fills leaves/computed of `f` for the given roots: a depth-first walk from the roots, in
// the order of the trace's fields so that statements follow the sweeps body by body.
void schedule(const symbolic::Trace& trace, const std::vector<int>& stage, const std::vector<NodeId>& roots,
              FunctionPlan& f) {
  const Graph& graph = trace.graph;
  std::set<NodeId> needed;
  {
    std::vector<NodeId> stack(roots.begin(), roots.end());
    while (!stack.empty()) {
      const NodeId id = stack.back();
      stack.pop_back();
      if (graph.node(id).op == Op::constant || !needed.insert(id).second) continue;
      if (is_leaf_here(graph, stage, id, f.stage)) continue;
      const Node& n = graph.node(id);
      for (int k = 0; k < symbolic::arity(n.op); ++k) stack.push_back(n.args[k]);
    }
  }
  std::set<NodeId> done;
  std::vector<int> blocks;  // per computed node: the block (anchor group) it is computed in
  int block = 0;
  // Depth first, operands in order, each node after its operands; an explicit stack of (node, next
  // operand), so that the depth of the graph is not the depth of the call stack.
  std::vector<std::pair<NodeId, int>> stack;
  const auto visit = [&](NodeId root) {
    const auto enter = [&](NodeId id) {
      if (!needed.count(id) || !done.insert(id).second) return;
      if (is_leaf_here(graph, stage, id, f.stage)) f.leaves.push_back(id);
      else stack.emplace_back(id, 0);
    };
    enter(root);
    while (!stack.empty()) {
      const auto [id, next] = stack.back();
      const Node& n = graph.node(id);
      if (next < symbolic::arity(n.op)) {
        ++stack.back().second;
        enter(n.args[next]);
        continue;
      }
      stack.pop_back();
      f.computed.push_back(id);
      blocks.push_back(block);
    }
  };
  for (const auto& field : trace.fields) {  // anchors in sweep order, one block each
    ++block;
    visit(field.node);
  }
  ++block;
  for (NodeId id : roots) visit(id);
  reduce_live_ranges(graph, f.computed, blocks);
}

std::vector<std::size_t> anchors(const symbolic::Trace& trace) {
  std::vector<std::size_t> anchor(trace.graph.size(), kNoAnchor);
  for (std::size_t f = 0; f < trace.fields.size(); ++f) {
    std::vector<NodeId> stack{trace.fields[f].node};
    while (!stack.empty()) {
      const NodeId id = stack.back();
      stack.pop_back();
      if (anchor[id] != kNoAnchor) continue;
      anchor[id] = f;
      const Node& n = trace.graph.node(id);
      for (int k = 0; k < symbolic::arity(n.op); ++k) stack.push_back(n.args[k]);
    }
  }
  return anchor;
}

// A carried node's State member: the field it is, sin/cos of the input it is, or the
// "_term" (numbered from the second on) of the field it is computed for.
// `first_field`: per node, the first trace field that is it.
std::string carried_member_name(const symbolic::Trace& trace, const Plan& plan, NodeId id,
                                const std::unordered_map<NodeId, std::size_t>& first_field,
                                std::map<std::string, int>& terms) {
  if (const auto found = first_field.find(id); found != first_field.end()) {
    const auto& field = trace.fields[found->second];
    return field_name(field, !is_state_field(field));
  }
  if (std::string name = function_of_input_name(trace, id); !name.empty()) return name;
  if (plan.anchor[id] == kNoAnchor) throw std::logic_error("carried node " + std::to_string(id) + " reaches no field");
  const auto& field = trace.fields[plan.anchor[id]];
  const std::string name = field_name(field, !is_state_field(field)) + "_term";
  const int count = ++terms[name];
  return count == 1 ? name : name + "_" + std::to_string(count);
}

// Marks every node in the cone of `roots` (through all stages, down to inputs).
void mark_cone(const Graph& graph, const std::vector<NodeId>& roots, std::vector<int>& marks) {
  std::vector<NodeId> stack(roots.begin(), roots.end());
  std::vector<bool> seen(graph.size(), false);
  while (!stack.empty()) {
    const NodeId id = stack.back();
    stack.pop_back();
    if (seen[id]) continue;
    seen[id] = true;
    ++marks[id];
    const Node& n = graph.node(id);
    for (int k = 0; k < symbolic::arity(n.op); ++k) stack.push_back(n.args[k]);
  }
}

void localise_single_policy_work(const symbolic::Trace& trace, const std::vector<FunctionPlan>& solves,
                                 bool expose_all, std::vector<int>& stage) {
  const Graph& graph = trace.graph;
  std::vector<int> solve_uses(graph.size(), 0), state_uses(graph.size(), 0);
  for (const auto& f : solves) {
    std::vector<NodeId> roots;
    for (std::size_t i : f.fields) roots.push_back(trace.fields[i].node);
    mark_cone(graph, roots, solve_uses);
  }
  if (expose_all) {
    std::vector<NodeId> roots;
    for (const auto& field : trace.fields)
      if (is_state_field(field)) roots.push_back(field.node);
    mark_cone(graph, roots, state_uses);
  }
  for (NodeId id = 0; id < graph.size(); ++id)
    if (stage[id] == symbolic::stage_decompose && graph.node(id).op != Op::input && solve_uses[id] == 1 &&
        state_uses[id] == 0)
      stage[id] = symbolic::stage_solve;
}

// Plan::guard from the roots down: a select_path node needed on every path hands each of its two
// value operands to one path; everything else inherits its users' guard, and a node that two
// different guards need is needed always. Node ids are topological (operands first).
void path_guards(const symbolic::Trace& trace, const std::vector<NodeId>& roots, Plan& plan) {
  const Graph& graph = trace.graph;
  constexpr int unset = -2;
  plan.guard.assign(graph.size(), unset);
  const auto merge = [&](NodeId id, int g) {
    int& current = plan.guard[id];
    current = current == unset || current == g ? g : kAlways;
  };
  for (NodeId root : roots) merge(root, kAlways);
  for (NodeId id = static_cast<NodeId>(graph.size()); id-- > 0;) {
    const int g = plan.guard[id];
    if (g == unset) continue;
    const Node& n = graph.node(id);
    int condition = -1;
    if (n.op == Op::select_path && g == kAlways) {
      condition = plan.condition_of(n);
      if (condition < 0) {
        condition = static_cast<int>(plan.conditions.size());
        plan.conditions.push_back({n.args[0], n.args[1]});
      }
    }
    for (int k = 0; k < symbolic::arity(n.op); ++k)
      merge(n.args[k], condition >= 0 && k >= 2 ? 2 * condition + (k - 2) : g);
  }
  for (int& g : plan.guard)
    if (g == unset) g = kAlways;
}

// The condition whose if/else computes node `id`: a guarded node's, or a select_path node's own
// (it is assigned in both branches); -1 for the rest.
int path_of(const Graph& graph, const Plan& plan, NodeId id) {
  if (plan.guard[id] != kAlways) return plan.guard[id] / 2;
  const Node& n = graph.node(id);
  return n.op == Op::select_path ? plan.condition_of(n) : -1;
}

// Gathers each condition's nodes into contiguous if/else blocks (FunctionPlan::path_block). One
// condition can need several blocks: the refinement (R1) solves with the same factorisation twice,
// the second time for setpoints that the first solution gives. A node's pass for condition c is
// the number of c's select_path results on its longest path of operands; a block is the nodes of
// c of one pass (the then and the else side, and the results). Emission is by demand in the
// order of `computed`: a node is placed after its operands, a block as a whole after every
// operand of its nodes outside it. No node outside a block of pass p needs that block unless
// its own pass is above p, and no node of the block needs it, so this order exists. A
// condition that depends on a later function's inputs cannot be tested here: its nodes are
// computed on every path; one of an earlier function is read from the State (it is carried:
// the select_path nodes of a later or this function read it).
void group_path_blocks(const Graph& graph, Plan& plan, FunctionPlan& f) {
  const auto testable = [&](int condition) {
    if (condition < 0) return false;
    const PathCondition& c = plan.conditions[condition];
    for (NodeId id : {c.greater, c.than}) {
      if (plan.stage[id] > f.stage) return false;
      if (plan.stage[id] < f.stage && graph.node(id).op != Op::constant &&
          std::find(f.leaves.begin(), f.leaves.end(), id) == f.leaves.end())
        f.leaves.push_back(id);
    }
    return true;
  };
  const std::size_t conditions = plan.conditions.size();
  std::unordered_map<NodeId, std::vector<int>> pass;  // per computed node, per condition
  std::unordered_map<NodeId, std::pair<int, int>> block_key;  // condition, pass
  for (NodeId id : f.computed) {
    std::vector<int> p(conditions, 0);
    const Node& n = graph.node(id);
    for (int k = 0; k < symbolic::arity(n.op); ++k) {
      const auto found = pass.find(n.args[k]);
      if (found == pass.end()) continue;
      const int result_of = plan.guard[n.args[k]] == kAlways ? path_of(graph, plan, n.args[k]) : -1;
      for (std::size_t c = 0; c < conditions; ++c)
        p[c] = std::max(p[c], found->second[c] + (result_of == static_cast<int>(c) ? 1 : 0));
    }
    const int condition = path_of(graph, plan, id);
    if (testable(condition)) block_key[id] = {condition, p[condition]};
    pass[id] = std::move(p);
  }
  std::map<std::pair<int, int>, std::vector<NodeId>> blocks;
  for (NodeId id : f.computed)
    if (block_key.count(id)) blocks[block_key[id]].push_back(id);

  std::vector<NodeId> order;
  std::vector<int> block_of;
  std::set<NodeId> placed;
  std::set<std::pair<int, int>> placed_blocks;
  int numbered = 0;
  // Depth first with an explicit stack (the graph's depth is not the call stack's): a node after
  // its operands; a block, entered through any of its nodes, after every operand outside it of
  // each of its members, in the members' order.
  struct Frame {
    NodeId id;
    const std::pair<int, int>* block;  // the block's key, or null for a node outside blocks
    std::size_t member = 0;
    int operand = 0;
  };
  std::vector<Frame> stack;
  const auto enter = [&](NodeId id) {
    if (!pass.count(id) || placed.count(id)) return;
    const auto key = block_key.find(id);
    if (key == block_key.end()) stack.push_back({id, nullptr});
    else if (placed_blocks.insert(key->second).second) stack.push_back({id, &key->second});
  };
  const auto place = [&](NodeId id, int block) {
    placed.insert(id);
    order.push_back(id);
    block_of.push_back(block);
  };
  for (NodeId root : f.computed) {
    enter(root);
    while (!stack.empty()) {
      Frame& top = stack.back();
      if (!top.block) {
        const Node& n = graph.node(top.id);
        if (top.operand < symbolic::arity(n.op)) {
          enter(n.args[top.operand++]);
          continue;
        }
        const NodeId id = top.id;
        stack.pop_back();
        place(id, 0);
        continue;
      }
      const std::pair<int, int> key = *top.block;
      const std::vector<NodeId>& members = blocks[key];
      bool entered = false;
      while (!entered && top.member < members.size()) {
        const Node& n = graph.node(members[top.member]);
        if (top.operand == symbolic::arity(n.op)) {
          ++top.member;
          top.operand = 0;
          continue;
        }
        const NodeId operand = n.args[top.operand++];
        const auto operand_key = block_key.find(operand);
        if (operand_key == block_key.end() || operand_key->second != key) {
          enter(operand);  // may grow the stack: `top` is not used after it
          entered = true;
        }
      }
      if (entered) continue;
      stack.pop_back();
      ++numbered;
      for (NodeId m : members) place(m, numbered);
    }
  }
  f.computed = std::move(order);
  f.path_block = std::move(block_of);
}

// Plan::guard over every function's fields, then each function's if/else blocks.
void place_path_blocks(const symbolic::Trace& trace, Plan& plan) {
  std::vector<NodeId> roots;
  for (const auto& f : plan.functions)
    for (std::size_t i : f.fields) roots.push_back(trace.fields[i].node);
  path_guards(trace, roots, plan);
  for (auto& f : plan.functions) group_path_blocks(trace.graph, plan, f);
}

}  // namespace

bool is_state_field(const symbolic::Field& field) {
  return field.group == "kinematics" || field.group == "articulated";
}

Plan make_plan(const symbolic::Trace& trace, bool expose_all) {
  Plan plan;
  plan.stage = node_stages(trace);
  plan.anchor = anchors(trace);

  std::vector<FunctionPlan> solves;
  for (const auto policy : trace.policies) {
    FunctionPlan f;
    f.name = std::string("solve_") + solver::name(policy);
    f.group = solver::name(policy);
    f.stage = symbolic::stage_solve;
    solves.push_back(f);
  }
  FunctionPlan outward, decompose;
  outward.name = "outward";
  outward.stage = symbolic::stage_outward;
  decompose.name = "decompose";
  decompose.stage = symbolic::stage_decompose;

  for (std::size_t i = 0; i < trace.fields.size(); ++i) {
    const symbolic::Field& field = trace.fields[i];
    if (is_state_field(field)) {
      if (!expose_all) continue;
      plan.state_fields.push_back(i);
      plan.exposed_field.emplace(field.node, i);
      (plan.stage[field.node] >= symbolic::stage_decompose ? decompose : outward).fields.push_back(i);
    } else if (field.output || expose_all) {
      for (auto& f : solves)
        if (f.group == field.group) f.fields.push_back(i);
    }
  }

  // Without setpoints (Nc = 0) there is nothing to re-solve for: driver-dependent work that
  // only one policy needs is done in that policy's solve, not in decompose() for all of them.
  if (trace.constraints == 0) localise_single_policy_work(trace, solves, expose_all, plan.stage);

  // Later functions first: what they read from earlier stages becomes carried.
  std::set<NodeId> carried;
  const auto plan_function = [&](FunctionPlan& f, std::vector<NodeId> roots) {
    for (std::size_t i : f.fields) roots.push_back(trace.fields[i].node);
    schedule(trace, plan.stage, roots, f);
    for (NodeId leaf : f.leaves)
      if (plan.stage[leaf] < f.stage && !plan.exposed_field.count(leaf)) carried.insert(leaf);
  };
  const auto carried_at = [&](int stage) {
    std::vector<NodeId> nodes;
    for (NodeId id : carried)
      if (plan.stage[id] == stage) nodes.push_back(id);
    return nodes;
  };
  for (auto& f : solves) plan_function(f, {});
  decompose.carried_out = carried_at(symbolic::stage_decompose);
  plan_function(decompose, decompose.carried_out);
  outward.carried_out = carried_at(symbolic::stage_outward);
  plan_function(outward, outward.carried_out);

  plan.functions.push_back(std::move(outward));
  plan.functions.push_back(std::move(decompose));
  for (auto& f : solves) plan.functions.push_back(std::move(f));
  std::unordered_map<NodeId, std::size_t> first_field;
  for (std::size_t i = trace.fields.size(); i-- > 0;) first_field[trace.fields[i].node] = i;
  std::map<std::string, int> terms;
  for (NodeId id : carried) plan.carried_name[id] = carried_member_name(trace, plan, id, first_field, terms);
  place_path_blocks(trace, plan);
  return plan;
}

Plan make_single_pass_plan(const symbolic::Trace& trace, const std::string& prefix) {
  Plan plan;
  plan.stage.assign(trace.graph.size(), symbolic::stage_solve);
  plan.anchor = anchors(trace);
  for (const auto policy : trace.policies) {
    FunctionPlan f;
    f.group = solver::name(policy);
    f.name = prefix + f.group;
    f.stage = symbolic::stage_solve;
    std::vector<NodeId> roots;
    for (std::size_t i = 0; i < trace.fields.size(); ++i)
      if (trace.fields[i].group == f.group && trace.fields[i].output) {
        f.fields.push_back(i);
        roots.push_back(trace.fields[i].node);
      }
    schedule(trace, plan.stage, roots, f);
    plan.functions.push_back(std::move(f));
  }
  place_path_blocks(trace, plan);
  return plan;
}

}  // namespace sweepgen::emit
