// Trace → plan → C++ text: the generated header, source, CUDA source and CMake snippet of one scene.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "emit/op_count.hpp"
#include "model/chain.hpp"
#include "solver/derivative_seeds.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::emit {

struct EmitRequest {
  std::string solver_namespace;       // C++ namespace, may contain '::'
  std::vector<std::string> scalars;   // "double" and/or "float"
  bool expose_all = false;            // store every intermediate in State / Solution
  symbolic::TraceRequest trace;       // drivers, fixed directions, policies, options
  std::string provenance;             // one line: generator version and input hashes
  bool check_inputs = true;           // emit the NaN/Inf checks raising status_not_finite
  // (I2) or (I6) (scene key constraint_rows); empty: the one with fewer operations, counted
  // (expose_all: the columns, which it lists).
  std::optional<solver::ConstraintRows> constraint_rows = std::nullopt;
  bool derivatives = false;           // emit derivatives_<policy> per differentiable policy (D1–D8)
  solver::DerivativeOutputs derivative_outputs{};  // the Jacobians they return (scene key derivatives)
};

struct EmittedFile {
  std::string name;  // file name, no directory
  std::string text;
};

struct FunctionCost {
  std::string scalar;
  std::string function;  // "outward", ..., or "full solve_<policy>" for the sum of the three
  OpCount ops;
};

struct EmittedSolver {
  std::vector<EmittedFile> files;  // header, source, CUDA source, CMake snippet
  std::vector<FunctionCost> costs;
  std::vector<std::string> choices;  // how the constraint is evaluated and factored, one line each
  // How the rows r_i were formed ((I2) or (I6)), what a reference solver needs to run the same
  // operations (`constraint_rows` of its options).
  solver::ConstraintRows constraint_rows = solver::ConstraintRows::inward_columns;
};

// File stem of a namespace: "a::b" -> "a__b", so that no two namespaces share one ("a_b" stays
// "a_b": a namespace's parts cannot hold "__", reserved in C++), and as long as the namespace.
std::string file_stem(const std::string& solver_namespace);

EmittedSolver emit_solver(const model::Chain& chain, const EmitRequest& request);

}  // namespace sweepgen::emit
