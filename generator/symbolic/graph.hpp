// A hash-consed expression graph: what the generator records when it runs the reference
// sweeps with the symbolic scalar. Nodes are created through Graph::make, which folds
// constants, applies the algebraic identities below and returns an existing node for an
// expression it has seen before (common subexpressions are shared by construction).
//   x+0 = x   x-0 = x   0-x = -x   x-x = 0   x*0 = 0   x*1 = x   x*(-1) = -x   x/1 = x
//   0/x = 0   -(-x) = x   a+(-b) = a-b   a-(-b) = a+b   select(a, b, x, x) = x
//   select(a, b, x, y) = (a > b ? x : y) for constants a, b (both for select_greater and select_path)
//   -(c*x) = (-c)*x for a constant c   select(select(a, b, 1, 0), t, x, y) = select(a, b, x, y), 0 <= t < 1
// x*0 = 0 assumes finite x: every input of a dynamics solve is (NaN checks live elsewhere).
// The graph holds numbers and operations only: what an input stands for is the tracer's
// (Trace::inputs), how anything is spelt in a target language is the emitter's.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace sweepgen::symbolic {

using NodeId = std::uint32_t;

enum class Op : std::uint8_t {
  constant,
  input,
  add,
  sub,
  mul,
  div,
  neg,
  sin,
  cos,
  abs,
  min,
  max,
  select_greater,  // args[0] > args[1] ? args[2] : args[3]
  equilibration_scale,  // the power of two s with s² x in [1, 4), 0 for x <= 0 (solver/scalar_ops.hpp)
  select_path,     // args[0] > args[1] ? args[2] : args[3], where only the taken operand need be computed:
                   // the emitter computes what only one path needs inside an if/else (Plan::guard)
  sqrt,
  atan2,           // atan2(args[0], args[1]): the angle of (x, y) = (args[1], args[0])
};

const char* op_name(Op op);
int arity(Op op);

struct Node {
  Op op = Op::constant;
  std::array<NodeId, 4> args{};
  double value = 0;      // Op::constant
  std::uint32_t input = 0;  // Op::input: its number, 0.. in creation order (what it stands for: Trace::inputs)
};

class Graph {
 public:
  Graph();

  NodeId constant(double value);
  NodeId input();  // a new input, numbered input_count() before the call
  NodeId make(Op op, NodeId a, NodeId b = 0, NodeId c = 0, NodeId d = 0);

  const Node& node(NodeId id) const { return nodes_[id]; }
  std::size_t size() const { return nodes_.size(); }
  std::uint32_t input_count() const { return input_count_; }
  bool is_constant(NodeId id, double value) const {
    return nodes_[id].op == Op::constant && nodes_[id].value == value;
  }

  // The nodes that `roots` reach, renumbered depth-first from the roots in their order (operands
  // in their stored order); `roots` are rewritten to the new ids. Why: ids follow the order the
  // tracer created nodes in, and C++ leaves the order in which operands are evaluated open (g++
  // and clang trace `a*b + c*d` in opposite orders). Operands of commutative operations are kept
  // in the order of their shape (a hash of the expression, not of ids), so the graph's structure
  // does not depend on that order; renumbering makes the ids, and so the emitted code, not depend
  // on it either.
  Graph canonical(std::vector<NodeId>& roots) const;

  // Values of every node for the given input values (for testing the trace itself).
  template <class Scalar>
  std::vector<Scalar> evaluate(const std::vector<Scalar>& input_values) const;

 private:
  NodeId intern(const Node& node);
  NodeId fold(Op op, const std::array<NodeId, 4>& args);
  // The order of operands of commutative operations: by shape, then (for distinct expressions of
  // one shape, a hash collision) by id.
  bool ordered_before(NodeId a, NodeId b) const;

  struct KeyHash {
    std::size_t operator()(const Node& n) const;
  };
  struct KeyEqual {
    bool operator()(const Node& a, const Node& b) const;
  };
  std::vector<Node> nodes_;
  std::vector<std::uint64_t> shapes_;  // per node: hash of op, value, input and operands' shapes
  std::uint32_t input_count_ = 0;
  std::unordered_map<Node, NodeId, KeyHash, KeyEqual> index_;
};

}  // namespace sweepgen::symbolic

#include "symbolic/graph_evaluate.hpp"
