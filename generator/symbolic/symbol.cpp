#include "symbolic/symbol.hpp"

#include <stdexcept>

namespace sweepgen::symbolic {
namespace {
thread_local Graph* current_graph = nullptr;
}

TraceScope::TraceScope(Graph& graph) : previous_(current_graph) { current_graph = &graph; }
TraceScope::~TraceScope() { current_graph = previous_; }

Graph& TraceScope::graph() {
  if (current_graph == nullptr) throw std::logic_error("symbolic::Symbol used outside a TraceScope");
  return *current_graph;
}

}  // namespace sweepgen::symbolic
