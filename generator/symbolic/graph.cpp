#include "symbolic/graph.hpp"

#include "solver/scalar_ops.hpp"

#include <cmath>
#include <cstring>
#include <utility>

namespace sweepgen::symbolic {
namespace {

bool commutative(Op op) { return op == Op::add || op == Op::mul || op == Op::min || op == Op::max; }

std::uint64_t bits(double value) {
  std::uint64_t b;
  std::memcpy(&b, &value, sizeof b);
  return b;
}

// splitmix64's finaliser: mixes one word into a well-spread hash.
std::uint64_t mix(std::uint64_t h, std::uint64_t word) {
  std::uint64_t z = h + word + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

const char* op_name(Op op) {
  switch (op) {
    case Op::constant: return "constant";
    case Op::input: return "input";
    case Op::add: return "add";
    case Op::sub: return "sub";
    case Op::mul: return "mul";
    case Op::div: return "div";
    case Op::neg: return "neg";
    case Op::sin: return "sin";
    case Op::cos: return "cos";
    case Op::abs: return "abs";
    case Op::min: return "min";
    case Op::max: return "max";
    case Op::select_greater: return "select";
    case Op::equilibration_scale: return "equilibration_scale";
    case Op::select_path: return "select_path";
    case Op::sqrt: return "sqrt";
    case Op::atan2: return "atan2";
  }
  return "?";
}

int arity(Op op) {
  switch (op) {
    case Op::constant:
    case Op::input: return 0;
    case Op::neg:
    case Op::sin:
    case Op::cos:
    case Op::abs:
    case Op::sqrt:
    case Op::equilibration_scale: return 1;
    case Op::select_greater:
    case Op::select_path: return 4;
    default: return 2;
  }
}

std::size_t Graph::KeyHash::operator()(const Node& n) const {
  std::size_t h = static_cast<std::size_t>(n.op) * 0x9E3779B97F4A7C15ull;
  for (NodeId a : n.args) h = (h ^ a) * 0x100000001B3ull;
  h ^= bits(n.value) + 0x9E3779B9u + (h << 6) + (h >> 2);
  return h ^ (static_cast<std::size_t>(n.input) << 17);
}

bool Graph::KeyEqual::operator()(const Node& a, const Node& b) const {
  return a.op == b.op && a.args == b.args && bits(a.value) == bits(b.value) && a.input == b.input;
}

Graph::Graph() { constant(0.0); }  // node 0 is the constant 0, the default of every symbol

NodeId Graph::intern(const Node& node) {
  const auto found = index_.find(node);
  if (found != index_.end()) return found->second;
  const NodeId id = static_cast<NodeId>(nodes_.size());
  nodes_.push_back(node);
  index_.emplace(node, id);
  std::uint64_t shape = mix(mix(static_cast<std::uint64_t>(node.op), bits(node.value)), node.input);
  for (int k = 0; k < arity(node.op); ++k) shape = mix(shape, shapes_[node.args[k]]);
  shapes_.push_back(shape);
  return id;
}

bool Graph::ordered_before(NodeId a, NodeId b) const {
  return shapes_[a] != shapes_[b] ? shapes_[a] < shapes_[b] : a < b;
}

Graph Graph::canonical(std::vector<NodeId>& roots) const {
  constexpr NodeId unset = ~NodeId(0);
  Graph out;
  out.input_count_ = input_count_;
  std::vector<NodeId> renamed(nodes_.size(), unset);
  renamed[0] = 0;  // the constant 0, node 0 of every graph
  std::vector<std::pair<NodeId, int>> stack;  // node, next operand to visit
  for (NodeId& root : roots) {
    stack.push_back({root, 0});
    while (!stack.empty()) {
      const NodeId id = stack.back().first;
      const Node& n = nodes_[id];
      if (renamed[id] != unset) {
        stack.pop_back();
      } else if (stack.back().second < arity(n.op)) {
        const NodeId operand = n.args[stack.back().second++];
        if (renamed[operand] == unset) stack.push_back({operand, 0});
      } else {
        Node copy = n;
        for (int k = 0; k < arity(n.op); ++k) copy.args[k] = renamed[n.args[k]];
        renamed[id] = out.intern(copy);
        stack.pop_back();
      }
    }
    root = renamed[root];
  }
  return out;
}

NodeId Graph::constant(double value) {
  Node n;
  n.op = Op::constant;
  n.value = value == 0 ? 0.0 : value;  // -0 and +0 are one node
  return intern(n);
}

NodeId Graph::input() {
  Node n;
  n.op = Op::input;
  n.input = input_count_++;
  return intern(n);
}

NodeId Graph::make(Op op, NodeId a, NodeId b, NodeId c, NodeId d) {
  std::array<NodeId, 4> args{a, b, c, d};
  for (int k = arity(op); k < 4; ++k) args[k] = 0;
  if (commutative(op) && ordered_before(args[1], args[0])) std::swap(args[0], args[1]);
  return fold(op, args);
}

NodeId Graph::fold(Op op, const std::array<NodeId, 4>& args) {
  const Node& x = nodes_[args[0]];
  const Node& y = nodes_[args[1]];
  const int n = arity(op);
  bool all_const = true;
  for (int k = 0; k < n; ++k) all_const = all_const && nodes_[args[k]].op == Op::constant;
  if (all_const) {
    const double u = x.value, v = y.value;
    switch (op) {
      case Op::add: return constant(u + v);
      case Op::sub: return constant(u - v);
      case Op::mul: return constant(u * v);
      case Op::div: return constant(u / v);
      case Op::neg: return constant(-u);
      case Op::sin: return constant(std::sin(u));
      case Op::cos: return constant(std::cos(u));
      case Op::abs: return constant(std::abs(u));
      case Op::sqrt: return constant(std::sqrt(u));
      case Op::atan2: return constant(std::atan2(u, v));
      case Op::min: return constant(std::min(u, v));
      case Op::max: return constant(std::max(u, v));
      case Op::select_greater:
      case Op::select_path: return u > v ? args[2] : args[3];
      case Op::equilibration_scale: return constant(solver::equilibration_scale(u));
      default: break;
    }
  }
  const auto is = [&](const Node& node, double value) { return node.op == Op::constant && node.value == value; };
  switch (op) {
    case Op::add:
      if (is(x, 0)) return args[1];
      if (is(y, 0)) return args[0];
      if (y.op == Op::neg) return make(Op::sub, args[0], y.args[0]);
      if (x.op == Op::neg) return make(Op::sub, args[1], x.args[0]);
      break;
    case Op::sub:
      if (is(y, 0)) return args[0];
      if (is(x, 0)) return make(Op::neg, args[1]);
      if (args[0] == args[1]) return constant(0);
      if (y.op == Op::neg) return make(Op::add, args[0], y.args[0]);
      break;
    case Op::mul:
      if (is(x, 0) || is(y, 0)) return constant(0);
      if (is(x, 1)) return args[1];
      if (is(y, 1)) return args[0];
      if (is(x, -1)) return make(Op::neg, args[1]);
      if (is(y, -1)) return make(Op::neg, args[0]);
      if (x.op == Op::neg) return make(Op::neg, make(Op::mul, x.args[0], args[1]));
      if (y.op == Op::neg) return make(Op::neg, make(Op::mul, args[0], y.args[0]));
      break;
    case Op::div:
      if (is(x, 0)) return constant(0);
      if (is(y, 1)) return args[0];
      if (is(y, -1)) return make(Op::neg, args[0]);
      if (x.op == Op::neg) return make(Op::neg, make(Op::div, x.args[0], args[1]));
      break;
    case Op::neg:
      if (x.op == Op::neg) return x.args[0];
      // -(c y) = (-c) y exactly: the sign goes into the constant.
      if (x.op == Op::mul) {
        const NodeId a = x.args[0], b = x.args[1];  // copies: constant() may grow nodes_
        if (nodes_[a].op == Op::constant) return make(Op::mul, constant(-nodes_[a].value), b);
        if (nodes_[b].op == Op::constant) return make(Op::mul, a, constant(-nodes_[b].value));
      }
      break;
    case Op::abs:
      if (x.op == Op::neg) return make(Op::abs, x.args[0]);
      break;
    case Op::select_greater:
      if (args[2] == args[3]) return args[2];
      if (x.op == Op::constant && y.op == Op::constant) return x.value > y.value ? args[2] : args[3];
      // (a > b ? 1 : 0) > t ? p : q  with 0 <= t < 1 is  a > b ? p : q.
      if (x.op == Op::select_greater && is(nodes_[x.args[2]], 1) && is(nodes_[x.args[3]], 0) && y.op == Op::constant &&
          y.value >= 0 && y.value < 1)
        return make(Op::select_greater, x.args[0], x.args[1], args[2], args[3]);
      break;
    case Op::select_path:
      if (args[2] == args[3]) return args[2];
      if (x.op == Op::constant && y.op == Op::constant) return x.value > y.value ? args[2] : args[3];
      break;
    default: break;
  }
  Node node;
  node.op = op;
  node.args = args;
  return intern(node);
}

}  // namespace sweepgen::symbolic
