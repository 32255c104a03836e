// The scene file: what the generator emits, for which chain, with which drivers. docs/scene.md is
// its reference: every key (scene_keys() below, the table the parser takes its keys from) with its
// type, default, meaning and an example. Keys not listed are errors, as are wrong types, duplicate
// keys and duplicate names; every error names file:line:column, the element and the reason.
//
// Driver instance names (torques and external forces) share one namespace: identifiers,
// unique, not C++ keywords, not 'bias' and not 'alpha'.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "model/urdf_loader.hpp"
#include "solver/derivative_seeds.hpp"
#include "solver/drivers.hpp"
#include "solver/flat_layout.hpp"
#include "solver/policy.hpp"
#include "solver/solver_model.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::scene {

constexpr int kSceneVersion = 1;

struct Scene {
  std::string path;    // the scene file as given ("" for default_scene)
  std::string solver;  // C++ namespace of the generated solver
  model::ChainSpec chain;  // urdf resolved against the scene file's directory
  Eigen::Vector3d gravity{0, 0, -9.81};
  solver::DriverLayout layout;  // tracks built; constraint sets with their fixed directions
  std::vector<solver::Policy> policies{solver::Policy::original};
  std::vector<std::string> scalars{"double"};
  bool expose_all = false;
  solver::ConstraintFactorisation constraint_factorisation = solver::ConstraintFactorisation::pivoted_ldlt;
  double pivot_tolerance = 0;  // 0: the default for the emitted scalar
  bool refinement = true;      // (R1)
  std::optional<solver::ConstraintRows> constraint_rows;  // (I2) or (I6); empty: auto (the cheaper)
  bool check_inputs = true;    // emit the NaN/Inf checks (status_not_finite)
  solver::SolveOutputs outputs{};  // the results the solves return (scene key outputs)
  bool derivatives = false;    // emit derivatives_<policy> (D1–D8)
  solver::DerivativeOutputs derivative_outputs{};  // their Jacobians (a list: those named; true: all)

  // "file:line:column" of elements that are checked against the chain later (load_scene_chain),
  // keyed by element: "urdf", "root", "tip", "rotor_inertia", "rotor_inertia.<joint>",
// "locked_joints", "locked_joints.<joint>",
  // "drivers.external_forces[i].link", "drivers.constraints", "drivers.constraints[i].link", "constraint_rows". A CLI flag overriding a field should set its entry to
  // the flag's name (e.g. locations["tip"] = "--tip").
  std::map<std::string, std::string> locations;
  // Numbers of the scene not taken as written (a fixed direction scaled to unit length), a
  // sentence each with its file:line:column: said by `generate` and `info` beside the URDF's.
  std::vector<std::string> notes;

  // Where `element` came from, for messages: its entry in `locations`, else the scene file,
  // else "command line".
  std::string location(const std::string& element) const;

  solver::SolverOptions solver_options() const;
  // Where the generated solver's flat entry points put each value, for a chain of `dof` joints.
  solver::FlatLayout flat_layout(const model::Chain& chain) const;
};

// Reads and validates the scene file (structure, types, names, ranges; everything that does not
// need the URDF). Throws InputError("file:line:column", element, reason) on anything invalid,
// YAML syntax errors included.
Scene load_scene(const std::string& path);

// Reads the scene's URDF into scene.chain.urdf_bytes, unless it has been read: every later
// load_scene_chain takes those bytes, so a command reads each input once. Errors as
// load_scene_chain's, at the scene's 'urdf' entry.
void read_scene_urdf(Scene& scene);

// Loads the scene's chain (model::load_chain) and checks the scene's names against it: rotor
// inertia joints exist, external-force links are on the chain and not fixed to the base, and
// solver::validate. Errors name the scene location of the offending entry; errors inside the
// URDF are reported at the scene's 'urdf' (or 'root'/'tip') entry with the URDF's own message.
model::Chain load_scene_chain(const Scene& scene);

// The scene used when there is no scene file (`--urdf --root --tip` only): namespace from the
// URDF file's stem (made a usable namespace, solver_namespace_problem: 'panda.urdf' -> panda,
// '7dof-arm.urdf' -> robot_7dof_arm, 'linux.urdf' -> robot_linux; cut to kMaxSolverNamespaceBytes);
// one torque instance "tau_ff"; one external force "f_ext_tip" on the tip link; Nc = 6 with
// run-time directions; every policy; decomposed (Alg. 2); scalars [double]; outputs only; default
// gravity and pivot tolerance. Loads the URDF to resolve an empty root/tip (so both are filled
// in); throws InputError if it cannot be loaded.
// `branch_tips` add tips (a tree; the constraint set stays on the first tip); snap_quarter_turns as ChainSpec's.
// `command` is what was run (e.g. "sweepgen info"): where no tip is named and the URDF's tree branches,
// the message says how to name one with it.
Scene default_scene(const std::string& urdf, const std::string& root = "", const std::string& tip = "",
                    const std::vector<std::string>& branch_tips = {}, bool snap_quarter_turns = true,
                    const std::string& command = "sweepgen generate");

// Every key of the scene format by its path: "drivers.torques" is key torques of the drivers
// mapping, "drivers.constraints[].link" key link of each mapping in the constraints list. The
// parser takes the keys of each mapping from this table; docs/scene.md documents each (type,
// default, meaning, example), and tests/test_scene_reference.cpp keeps the two in step.
const std::vector<std::string>& scene_keys();

}  // namespace sweepgen::scene
