// How generated code names what the trace computes: the C++ spelling of every input, the
// locals and State members named from the math (articulated_inertia_3_4, sin_q_2,
// bias_acceleration_3_1_term), and where stored fields live. One place, so the planner (State
// members) and the writer (locals) agree.
#pragma once

#include <string>

#include "symbolic/trace.hpp"

namespace sweepgen::emit {

// The argument or Drivers member that holds a traced input: "q[3]", "drivers.tau_ff[2]",
// "drivers.alpha[1][4]", "beta[0]".
std::string input_spelling(const symbolic::Trace& trace, const symbolic::Input& input);

// The local a traced input is loaded into: "q_3", "drivers_tau_ff_2", "beta_0", and a run-time
// direction "alpha_1_4". The instances' locals are drivers_<name>_<index>, one per name and index;
// a direction's two indices behind "drivers_alpha" would spell a torque alpha_1's.
std::string input_local_name(const symbolic::Trace& trace, const symbolic::Input& input);

// "<array>_<body>_<component>", with "<group>_" in front for a solve's own field when asked.
std::string field_name(const symbolic::Field& field, bool with_group);

// The name of a node that is not itself a field: sin/cos of an input ("sin_q_2"), or empty.
std::string function_of_input_name(const symbolic::Trace& trace, symbolic::NodeId id);

// How a Solution array is stored: values in Scalar, flags as bool (saturated), counts as one
// int (dropped_pivots, locked_joints). The State keeps every value in Scalar (later sweeps
// compute with it).
enum class Storage { value, flag, count };
Storage solution_storage(const std::string& array);

// Where stored values live in generated code.
std::string state_field_access(const symbolic::Field& field);     // state.<array>[body][component]
std::string solution_field_access(const symbolic::Field& field);  // out.<array>[...], out.<count>
std::string field_access(const symbolic::Field& field);           // whichever of the two holds it

// `target = value;` for a field (nullptr: a carried State member), converting a Scalar value
// to the field's storage; `constant`: the value is this number (a flag is then written
// true/false, a count as an integer).
std::string store_statement(const std::string& target, const symbolic::Field* field, const std::string& value,
                            const double* constant = nullptr);

}  // namespace sweepgen::emit
