// The text of the generated structs and flat layouts: State, Solution and Drivers members, the
// flat entry points' unpacking, packing and NaN/Inf checks, in the order of solver::FlatLayout
// (solver/flat_layout.hpp). Filled into templates/ by solver_emitter.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "solver/flat_layout.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::emit {

// The member types of a struct: the header's (one state), or its twin's in the generated source
// (a Batch of states, templates/lanes.mustache).
struct MemberTypes {
  std::string value, flag, count;
};
inline const MemberTypes kScalarMembers{"Scalar", "bool", "int"};
inline const MemberTypes kBatchMembers{"Batch", "Lanes<Batch>::Flag", "Lanes<Batch>::Count"};

// Array declarations "  Scalar name[rows][columns];" for the given fields, in first-seen order;
// in a Solution, flags as bool and counts as one int (names.hpp, Storage).
std::string array_members(const symbolic::Trace& trace, const std::vector<std::size_t>& fields, std::size_t bodies,
                          bool solution, const MemberTypes& types = kScalarMembers);

// The Drivers struct's members, of value type `type`.
std::string drivers_members(const symbolic::TraceRequest& request, const std::string& type);
// The FlatDrivers<Scalar> view of a Drivers' members (templates/solver.cpp.mustache, drivers_view_of).
std::string drivers_view_init(const symbolic::TraceRequest& request);
// drivers_from_flat(): the drivers read from the flat input, in order.
std::string unpack_drivers(const symbolic::TraceRequest& request);
// The members of FlatDrivers<S> (templates/solver.cpp.mustache): the Drivers arrays as views of a
// flat input, read in place; and the braced list that points them into `drivers_in`.
std::string flat_drivers_members(const symbolic::TraceRequest& request);
std::string flat_drivers_init(const symbolic::TraceRequest& request);
// decompose(): NaN/Inf among the drivers (scene: check_inputs).
std::string check_drivers(const symbolic::TraceRequest& request);
// The order of solver::FlatLayout's `in`, as the header documents it.
std::string flat_in(const symbolic::TraceRequest& request, std::size_t nc, bool floating_base, std::size_t couplings = 0);
// The order of solver::FlatLayout's `out` (scene key outputs).
std::string flat_out(const solver::SolveOutputs& outputs, std::size_t sets, std::size_t loops, std::size_t couplings = 0);
// The flat solve's output written from a Solution.
std::string pack_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets, std::size_t loops,
                          std::size_t couplings = 0);
// solve_<policy>(): NaN/Inf among the setpoints and the results (scene: check_inputs).
std::string check_solution(const solver::SolveOutputs& outputs, std::size_t nc, std::size_t sets, std::size_t loops,
                           std::size_t couplings = 0);

}  // namespace sweepgen::emit
