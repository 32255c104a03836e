#include "emit/constant_check.hpp"

#include <cmath>
#include <sstream>

#include "model/error.hpp"
#include "model/inert_text.hpp"

namespace sweepgen::emit {
namespace {

using symbolic::Field;
using symbolic::Node;
using symbolic::NodeId;
using symbolic::Op;

// Whether `value` is a constant the generated code can hold in `scalar`: not NaN, and not a finite
// number that the scalar rounds to Inf (emit/literal.hpp spells an Inf of the trace, an unlimited
// joint's effort bound, as HUGE_VAL; a float overflow it would spell "inff").
bool representable(double value, const std::string& scalar) {
  if (std::isnan(value)) return false;
  return !std::isfinite(value) || scalar != "float" || std::isfinite(static_cast<float>(value));
}

bool reads_bad_constant(const symbolic::Graph& graph, NodeId id, const std::string& scalar) {
  const Node& n = graph.node(id);
  if (n.op == Op::constant) return !representable(n.value, scalar);
  for (int k = 0; k < symbolic::arity(n.op); ++k) {
    const Node& operand = graph.node(n.args[k]);
    if (operand.op == Op::constant && !representable(operand.value, scalar)) return true;
  }
  return false;
}

// "constraint_energy of body 0 (link 'base_link'), component 3".
std::string field_text(const Field& field, const model::Chain& chain) {
  std::string text = field.array;
  if (field.body >= 0 && static_cast<std::size_t>(field.body) <= chain.dof())
    text += " of body " + std::to_string(field.body) + " (link " + quote_name(chain.bodies[field.body].link) + ")";
  return text + ", component " + std::to_string(field.component);
}

// The numbers the constants were folded from, as far as they go wrong: gravity, and the range of
// the bodies' masses and of their rotational inertias about their origins (nonzero ones).
std::string model_numbers(const model::Chain& chain, const solver::SolverOptions& options) {
  std::ostringstream text;
  text << "gravity [" << options.gravity[0] << ", " << options.gravity[1] << ", " << options.gravity[2] << "]";
  const auto range = [&](const std::string& what, const std::string& unit, auto&& value_of) {
    std::size_t smallest = 0, largest = 0;
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const double v = value_of(chain.bodies[i]);
      if (v == 0) continue;
      if (smallest == 0 || v < value_of(chain.bodies[smallest])) smallest = i;
      if (largest == 0 || v > value_of(chain.bodies[largest])) largest = i;
    }
    if (largest == 0) return;
    text << "; " << what << " from " << value_of(chain.bodies[smallest]) << " " << unit << " (link "
         << quote_name(chain.bodies[smallest].link) << ") to " << value_of(chain.bodies[largest]) << " " << unit
         << " (link " << quote_name(chain.bodies[largest].link) << ")";
  };
  range("masses", "kg", [](const model::Body& b) { return b.mass; });
  range("rotational inertias", "kg m^2", [](const model::Body& b) { return b.inertia.A.diagonal().cwiseAbs().maxCoeff(); });
  return text.str();
}

}  // namespace

void check_constants_finite(const symbolic::Trace& trace, const Plan& plan, const model::Chain& chain,
                            const solver::SolverOptions& options, const std::string& scalar) {
  const auto fail = [&](const FunctionPlan& f, std::size_t field) {
    throw InputError(chain.source, "generated " + f.name,
                     (field == kNoAnchor ? std::string("a value") : field_text(trace.fields[field], chain)) + " is computed from a constant that is NaN or too large for " + scalar +
                         ": the robot's or the scene's numbers are far outside a robot's range (" +
                         model_numbers(chain, options) + ")");
  };
  for (const FunctionPlan& f : plan.functions) {
    for (std::size_t i : f.fields)
      if (reads_bad_constant(trace.graph, trace.fields[i].node, scalar)) fail(f, i);
    for (NodeId id : f.computed)
      if (reads_bad_constant(trace.graph, id, scalar)) fail(f, plan.anchor[id]);
  }
}

}  // namespace sweepgen::emit
