// Splits a traced solver into the generated functions, by dependency (style.md, item 3):
//   outward()          everything that depends on q, q̇ only (kinematics, articulated
//                      inertias, the bias track, and F^A_cstr / E^A_cstr when α is fixed),
//   decompose()        what depends on the drivers τff, F_ext, α,
//   solve_<policy>()   what depends on the setpoints E_cstr,
// so that re-solving for new setpoints redoes only the last part. A node is computed in the
// function of the latest stage among its inputs; a value a later function needs is stored in
// the State ("carried", under the name of the field it is, or is a term of). Only what the outputs (and, with expose: all, the intermediates)
// need is computed at all.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "symbolic/trace.hpp"

namespace sweepgen::emit {

using symbolic::NodeId;

struct FunctionPlan {
  std::string name;               // "outward", "decompose", "solve_original", ...
  int stage = 0;
  std::string group;              // the policy name of a solve function
  std::vector<std::size_t> fields;   // trace.fields this function assigns (State or Solution)
  std::vector<NodeId> carried_out;   // nodes it stores for later functions
  std::vector<NodeId> leaves;        // inputs of its stage and earlier values it reads
  std::vector<NodeId> computed;      // nodes it computes, in emission order
  // Per computed node: 0, or the number (from 1) of the if/else of a path condition it is in
  // (Plan::guard): the nodes of one such block are contiguous in `computed`.
  std::vector<int> path_block;
};

// A condition `greater > than` of Op::select_path nodes: where it holds only their first
// operands are needed, elsewhere only their second.
struct PathCondition {
  NodeId greater;
  NodeId than;
};
constexpr int kAlways = -1;

constexpr std::size_t kNoAnchor = ~std::size_t(0);

struct Plan {
  std::vector<int> stage;                      // per node
  // Per node, the trace field whose computation it belongs to: the first field, in sweep order,
  // whose expression reaches it (kNoAnchor: none). Its banner in the emitted code, and its name
  // when it is carried.
  std::vector<std::size_t> anchor;
  std::vector<FunctionPlan> functions;         // outward, decompose, solve_<policy>...
  std::map<NodeId, std::string> carried_name;  // State member of each carried node, named from the math
  std::map<NodeId, std::size_t> exposed_field; // a State field already storing the node
  std::vector<std::size_t> state_fields;       // fields stored in the State (expose: all)
  std::vector<PathCondition> conditions;       // of the select_path nodes the functions need
  // The index in `conditions` of a select_path node's condition, -1 if it is not listed.
  int condition_of(const symbolic::Node& select) const {
    for (std::size_t c = 0; c < conditions.size(); ++c)
      if (conditions[c].greater == select.args[0] && conditions[c].than == select.args[1]) return static_cast<int>(c);
    return -1;
  }
  // Per node: kAlways, or 2 c + 0 / 2 c + 1 where only the taken / the other path of condition c
  // needs it (every use of the node is on that path): it is computed inside that path's branch.
  std::vector<int> guard;
};

// `expose_all`: every kinematics/articulated field is a State member and every solution
// field a Solution member; otherwise only the solution outputs are.
Plan make_plan(const symbolic::Trace& trace, bool expose_all);

// One function per policy of `trace`, named `prefix` + policy, computing its output fields from
// the inputs alone (every node in the one function, nothing carried, no State): the derivative
// functions (symbolic/trace_derivatives.hpp), whose Jacobians in q need every stage at once.
Plan make_single_pass_plan(const symbolic::Trace& trace, const std::string& prefix);

// Whether trace.fields[f] belongs to the State (kinematics, articulated) or a Solution.
bool is_state_field(const symbolic::Field& field);

}  // namespace sweepgen::emit
