#include "emit/names.hpp"

#include "emit/function_plan.hpp"

namespace sweepgen::emit {

std::string input_spelling(const symbolic::Trace& trace, const symbolic::Input& input) {
  using symbolic::Quantity;
  const auto at = [](std::uint32_t i) { return "[" + std::to_string(i) + "]"; };
  switch (input.quantity) {
    case Quantity::joint_position:
    case Quantity::base_rotation: return "q" + at(input.index);
    case Quantity::joint_velocity: return "qd" + at(input.index);
    case Quantity::feedforward_torque: return "drivers." + trace.layout.torques.at(input.instance) + at(input.index);
    case Quantity::external_force:
      return "drivers." + trace.layout.external_forces.at(input.instance).name + at(input.index);
    case Quantity::constraint_direction: return "drivers.alpha" + at(input.instance) + at(input.index);
    case Quantity::energy_setpoint: return "beta" + at(input.index);
  }
  return "";
}

namespace {

// An identifier for a spelling: "drivers.tau_ff[2]" -> "drivers_tau_ff_2".
std::string identifier(const std::string& spelling) {
  std::string name;
  for (char c : spelling) {
    if (c == '.' || c == '[') name += '_';
    else if (c != ']') name += c;
  }
  return name;
}

}  // namespace

std::string input_local_name(const symbolic::Trace& trace, const symbolic::Input& input) {
  const std::string name = identifier(input_spelling(trace, input));
  const std::string instances = "drivers_";
  return input.quantity == symbolic::Quantity::constraint_direction ? name.substr(instances.size()) : name;
}

std::string field_name(const symbolic::Field& field, bool with_group) {
  std::string name = with_group ? field.group + "_" : "";
  name += field.array;
  if (field.body >= 0) name += "_" + std::to_string(field.body);
  return name + "_" + std::to_string(field.component);
}

std::string function_of_input_name(const symbolic::Trace& trace, symbolic::NodeId id) {
  const symbolic::Node& n = trace.graph.node(id);
  if ((n.op != symbolic::Op::sin && n.op != symbolic::Op::cos) || trace.graph.node(n.args[0]).op != symbolic::Op::input)
    return "";
  return std::string(symbolic::op_name(n.op)) + "_" +
         input_local_name(trace, trace.inputs[trace.graph.node(n.args[0]).input]);
}

std::string state_field_access(const symbolic::Field& field) {
  const std::string body = field.body >= 0 ? "[" + std::to_string(field.body) + "]" : "";
  return "state." + field.array + body + "[" + std::to_string(field.component) + "]";
}

std::string field_access(const symbolic::Field& field) {
  return is_state_field(field) ? state_field_access(field) : solution_field_access(field);
}

Storage solution_storage(const std::string& array) {
  if (array == "saturated") return Storage::flag;
  if (array == "dropped_pivots" || array == "locked_joints") return Storage::count;
  return Storage::value;
}

std::string solution_field_access(const symbolic::Field& field) {
  std::string access = "out." + field.array;
  if (solution_storage(field.array) == Storage::count) return access;
  if (field.body >= 0) access += "[" + std::to_string(field.body) + "]";
  return access + "[" + std::to_string(field.component) + "]";
}

std::string store_statement(const std::string& target, const symbolic::Field* field, const std::string& value,
                            const double* constant) {
  const Storage storage = field && !is_state_field(*field) ? solution_storage(field->array) : Storage::value;
  switch (storage) {
    case Storage::flag:
      if (constant) return target + " = Lanes<S>::flag(" + (*constant != 0 ? "true);" : "false);");
      return target + " = " + value + " != 0;";
    case Storage::count:
      if (constant) return target + " = Lanes<S>::count(" + std::to_string(static_cast<long long>(*constant)) + ");";
      return target + " = Lanes<S>::count(" + value + ");";
    case Storage::value: break;
  }
  if (constant) return target + " = Lanes<S>::of(" + value + ");";  // a Batch takes it in every lane
  return target + " = " + value + ";";
}

}  // namespace sweepgen::emit
