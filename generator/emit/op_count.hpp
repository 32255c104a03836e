// Floating-point operations of generated code, by kind (the generator's cost model).
#pragma once

#include <cstddef>
#include <string>

#include "symbolic/graph.hpp"

namespace sweepgen::emit {

struct OpCount {
  std::size_t add = 0;      // + and -
  std::size_t mul = 0;
  std::size_t div = 0;      // and sqrt
  std::size_t neg = 0;      // sign flips
  std::size_t trig = 0;     // sin, cos, atan2
  std::size_t compare = 0;  // abs, min, max, select, equilibration_scale

  void count(symbolic::Op op);
  std::size_t total() const { return add + mul + div + neg + trig + compare; }
  OpCount& operator+=(const OpCount& o);
  // "add 123, mul 456, div 7, neg 8, sin/cos 14, compare 3 (total 611)"
  std::string summary() const;
};

}  // namespace sweepgen::emit
