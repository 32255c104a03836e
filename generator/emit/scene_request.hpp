// What the emitter needs from a scene: one translation, used by `sweepgen generate`, `info`
// and `report`.
#pragma once

#include <string>

#include "emit/solver_emitter.hpp"
#include "scene/scene.hpp"

namespace sweepgen::emit {

inline EmitRequest emit_request(const scene::Scene& s, const std::string& provenance) {
  EmitRequest request;
  request.solver_namespace = s.solver;
  request.scalars = s.scalars;
  request.expose_all = s.expose_all;
  request.check_inputs = s.check_inputs;
  request.derivatives = s.derivatives;
  request.derivative_outputs = s.derivative_outputs;
  request.trace.layout = s.layout;
  request.trace.policies = s.policies;
  request.trace.options = s.solver_options();
  request.trace.outputs = s.outputs;
  request.constraint_rows = s.constraint_rows;
  request.provenance = provenance;
  return request;
}

}  // namespace sweepgen::emit
