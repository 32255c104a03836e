// The symbolic scalar: runs the reference sweeps and records what they compute into the
// Graph made current by a TraceScope. Every arithmetic operation becomes Graph::make, so the
// recorded expressions are folded and shared as they are built.
#pragma once

#include <Eigen/Core>

#include "symbolic/graph.hpp"

namespace sweepgen::symbolic {

class Symbol;

// Makes `graph` the one that Symbol operations record into, for the scope's lifetime.
class TraceScope {
 public:
  explicit TraceScope(Graph& graph);
  ~TraceScope();
  TraceScope(const TraceScope&) = delete;
  TraceScope& operator=(const TraceScope&) = delete;
  static Graph& graph();

 private:
  Graph* previous_;
};

class Symbol {
 public:
  Symbol() : id_(0) {}  // the constant 0
  Symbol(double value) : id_(TraceScope::graph().constant(value)) {}  // NOLINT: implicit, as for double
  Symbol(int value) : Symbol(static_cast<double>(value)) {}            // NOLINT
  static Symbol from_node(NodeId id) {
    Symbol s;
    s.id_ = id;
    return s;
  }
  NodeId id() const { return id_; }

  Symbol& operator+=(const Symbol& o) { return *this = *this + o; }
  Symbol& operator-=(const Symbol& o) { return *this = *this - o; }
  Symbol& operator*=(const Symbol& o) { return *this = *this * o; }
  Symbol& operator/=(const Symbol& o) { return *this = *this / o; }

  friend Symbol operator+(const Symbol& a, const Symbol& b) { return make(Op::add, a, b); }
  friend Symbol operator-(const Symbol& a, const Symbol& b) { return make(Op::sub, a, b); }
  friend Symbol operator*(const Symbol& a, const Symbol& b) { return make(Op::mul, a, b); }
  friend Symbol operator/(const Symbol& a, const Symbol& b) { return make(Op::div, a, b); }
  friend Symbol operator-(const Symbol& a) { return make(Op::neg, a); }
  friend Symbol operator+(const Symbol& a) { return a; }

  friend Symbol sin(const Symbol& a) { return make(Op::sin, a); }
  friend Symbol cos(const Symbol& a) { return make(Op::cos, a); }
  friend Symbol abs_value(const Symbol& a) { return make(Op::abs, a); }
  friend Symbol sqrt(const Symbol& a) { return make(Op::sqrt, a); }
  friend Symbol atan2(const Symbol& y, const Symbol& x) { return make(Op::atan2, y, x); }
  friend Symbol equilibration_scale(const Symbol& a) { return make(Op::equilibration_scale, a); }
  friend Symbol refined_value(const Symbol& refined, const Symbol& /*first_pass*/) { return refined; }
  friend Symbol minimum(const Symbol& a, const Symbol& b) { return make(Op::min, a, b); }
  friend Symbol maximum(const Symbol& a, const Symbol& b) { return make(Op::max, a, b); }
  friend Symbol select_greater(const Symbol& a, const Symbol& b, const Symbol& x, const Symbol& y) {
    return from_node(TraceScope::graph().make(Op::select_greater, a.id_, b.id_, x.id_, y.id_));
  }
  friend Symbol select_path(const Symbol& a, const Symbol& b, const Symbol& x, const Symbol& y) {
    return from_node(TraceScope::graph().make(Op::select_path, a.id_, b.id_, x.id_, y.id_));
  }

 private:
  static Symbol make(Op op, const Symbol& a, const Symbol& b = Symbol()) {
    return from_node(TraceScope::graph().make(op, a.id_, b.id_));
  }
  NodeId id_;
};

}  // namespace sweepgen::symbolic

namespace Eigen {
template <>
struct NumTraits<sweepgen::symbolic::Symbol> : GenericNumTraits<sweepgen::symbolic::Symbol> {
  using Real = sweepgen::symbolic::Symbol;
  using NonInteger = sweepgen::symbolic::Symbol;
  using Nested = sweepgen::symbolic::Symbol;
  using Literal = sweepgen::symbolic::Symbol;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 1,
  };
};
}  // namespace Eigen
