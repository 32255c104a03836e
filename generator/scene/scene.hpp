// The scene file: what the generator emits, for which chain, with which drivers.
//
// Scene file schema, version 1 (YAML). Keys not listed are errors, as are wrong types,
// duplicate keys and duplicate names; every error names file:line:column, the element and
// the reason.
//
//   sweepgen_scene: 1               # required: schema version (integer; only 1 exists)
//   solver: panda_nc6               # required: C++ namespace of the generated solver; one
//                                   #   identifier or several joined by '::' (e.g. robots::panda);
//                                   #   no C++ keywords, no reserved names ('__', '_X'), not 'std'
//   urdf: ../panda/panda.urdf       # required: URDF file, relative to the scene file's
//                                   #   directory (absolute paths work too)
//   root: panda_link0               # optional: root (base) link; default: the URDF's root
//   tip: panda_hand                 # optional: tip link (constraint frame); default: the deepest
//                                   #   link below the root, if nothing branches
//   # tips: [left_hand, right_hand] # ... or several tips: the moving joints on the paths from
//                                   #   the root to each form a tree (shared trunk once); the
//                                   #   first tip is `tip` (tip_acceleration's frame); not with
//                                   #   'tip'. Constraint sets and forces may act on any of its links
//   base: fixed                     # optional: 'fixed' (default) or 'floating': the root link
//                                   #   moves freely (docs/derivation.md, F5); the generated q
//                                   #   starts with its orientation world_R_base (9, row-major),
//                                   #   qd, qdd and the torques with its six coordinates (twist
//                                   #   [omega; v] in its frame, spatial acceleration, wrench)
//   gravity: [0, 0, -9.81]          # optional: gravity in the root frame, or the world's for a
//                                   #   floating base [m/s^2]; default [0, 0, -9.81]
//   rotor_inertia:                  # optional: armature d_i (>= 0) by moving-joint name;
//     panda_joint1: 0.1             #   joints not listed get 0
//   snap_quarter_turns: true        # optional: true (default) takes URDF angles within 1e-10 rad of
//                                   #   a multiple of pi/2 as exact (they fold; each such <origin> is
//                                   #   listed by `sweepgen info`, generate and the header); false
//                                   #   takes the URDF literally
//   locked_joints:                  # optional: position [rad or m] by name of a moving joint
//     panda_finger_joint1: 0.04     #   off the chain (a gripper's fingers, a second arm), or of a
//                                   #   <mimic> joint on it (else its own degree of freedom): the
//                                   #   links behind it are lumped into the body that carries
//                                   #   them, with the joint held there; within the joint's
//                                   #   limits. Off-chain joints not listed are locked at 0
//                                   #   clamped into their limits. `sweepgen info` and the
//                                   #   generated header list every lumped, locked and left-out
//                                   #   link with its mass
//   drivers:                        # optional: no drivers (bias only, Nc = 0) when absent
//     torques: [tau_ff]             # optional: feed-forward torque instances (identifiers)
//     external_forces:              # optional: external wrench instances, each acting on a
//       - {name: contact, link: panda_link5}   # link of the chain (not fixed to the base),
//                                   #   given in that link's frame about its origin
//     constraints: 6                # optional: Nc in 0..6; the directions (alpha, tip frame)
//                                   #   are run-time inputs of the generated code; default 0
//     # constraints:                # ... or fixed directions folded into the code:
//     #   directions: [[0,0,0,1,0,0], [0,0,0,0,1,0]]   # unit 6-vectors [moment; force] in the
//                                   #   tip frame (|v| = 1 within 1e-9), at most 6; Nc = count
//     # constraints:                # ... or constraint sets on any links of the chain, each
//     #   - {link: panda_link4, count: 1}           # with its own directions, run-time (count,
//     #   - {link: panda_hand, directions: [[0,0,0,0,0,1]]}  # 1..6) or fixed (as above), in
//                                   #   that link's frame; one set per link; directions are
//                                   #   numbered in list order (alpha, beta, nu); each set's
//                                   #   link acceleration is an output (set_acceleration). The
//                                   #   sets must not over-determine the robot: no group of sets
//                                   #   may hold more directions than the joints that move their
//                                   #   links
//   decomposition: decomposed       # optional: 'composed' (one track, Alg. 1), 'decomposed'
//                                   #   (bias and every instance on a track of its own, Alg. 2;
//                                   #   the default), or a list of groups, each a list of
//                                   #   instance names sharing one track, e.g.
//                                   #   [[bias, tau_ff], [contact, push]]; 'bias' names the
//                                   #   velocity-product terms; an instance may be in at most one
//                                   #   group; everything not named (the bias too) gets a track
//                                   #   of its own. A group's track is named after its first
//                                   #   member; the tracks are the groups in the order given,
//                                   #   then the unnamed ones (bias, torques, external forces).
//   policies: [original, prioritize_external, saturate, saturate_exact]
//                                   # optional: solver-sweep policies to emit, no duplicates;
//                                   #   default [original]. prioritize_external (Alg. 4) needs
//                                   #   every external force on a track without the bias or
//                                   #   torques (so not with 'composed').
//   scalars: [double, float]        # optional: scalar types to emit, no duplicates;
//                                   #   default [double]
//   expose: outputs                 # optional: 'outputs' (default) or 'all' intermediates
//   constraint_factorisation: pivoted_ldlt  # optional: pivoted_ldlt (default) drops directions
//                                   #   whose pivot is below the tolerance (exact where kept);
//                                   #   damped solves (E + t I) after equilibration (damped
//                                   #   least squares: every direction kept, biased by ~t cond)
//   pivot_tolerance: 1e-12          # optional: relative tolerance of the constraint
//                                   #   factorisation (pivot threshold, or damping when damped),
//                                   #   0 < t < 1; default: 1000 * epsilon of the emitted scalar
//   refinement: true                # optional: true (default) or false. When true, the original
//                                   #   policy (and saturate_exact before its clamp) refines ν once
//                                   #   from the constraint's residual, with the pivoted
//                                   #   factorisation (docs/derivation.md, (R1)): about a tenth more
//                                   #   work per solve for errors near a dense KKT solve's
//   constraint_rows: auto           # optional: how the rows r_i = S_i^T F^A_cstr,i are formed:
//                                   #   inward_columns (I2), outward_rows (I6, not with expose:
//                                   #   all), or auto (default): the generator counts both and
//                                   #   emits the cheaper, the columns' count weighted by 21/20
//                                   #   past two directions (they spill; the header says which)
//   check_inputs: true              # optional: true (default) or false. When true, the generated
//                                   #   code checks every input (q, qd, drivers, beta) and output
//                                   #   for NaN/Inf and raises status_not_finite; false leaves the
//                                   #   checks out (bench/README.md gives their cost)
//   derivatives: false              # optional: false (default), true, or a list of the outputs
//                                   #   whose Jacobians are wanted, e.g. [qdd, nu]. Otherwise than
//                                   #   false, the generated code gains per differentiable policy
//                                   #   (original, prioritize_external; at least one listed) a
//                                   #   function derivatives_<policy> returning q̈, ν, τcmd and the
//                                   #   Jacobians of qdd, nu and tau_cmd (true) or of those listed,
//                                   #   w.r.t. q, qd, tau_ff, beta (docs/derivation.md, (D1)–(D3));
//                                   #   what is not listed is not computed. Needs a torque driver
//                                   #   (the tau_ff columns); nu only with constraint directions
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
  bool derivatives = false;    // emit derivatives_<policy> (D1–D8)
  solver::DerivativeOutputs derivative_outputs{};  // their Jacobians (a list: those named; true: all)

  // "file:line:column" of elements that are checked against the chain later (load_scene_chain),
  // keyed by element: "urdf", "root", "tip", "rotor_inertia", "rotor_inertia.<joint>",
// "locked_joints", "locked_joints.<joint>",
  // "drivers.external_forces[i].link", "drivers.constraints", "drivers.constraints[i].link", "constraint_rows". A CLI flag overriding a field should set its entry to
  // the flag's name (e.g. locations["tip"] = "--tip").
  std::map<std::string, std::string> locations;

  // Where `element` came from, for messages: its entry in `locations`, else the scene file,
  // else "command line".
  std::string location(const std::string& element) const;

  solver::SolverOptions solver_options() const;
  // Where the generated solver's flat entry points put each value, for a chain of `dof` joints.
  solver::FlatLayout flat_layout(std::size_t dof) const;
};

// Reads and validates the scene file (structure, types, names, ranges; everything that does not
// need the URDF). Throws InputError("file:line:column", element, reason) on anything invalid,
// YAML syntax errors included.
Scene load_scene(const std::string& path);

// Loads the scene's chain (model::load_chain) and checks the scene's names against it: rotor
// inertia joints exist, external-force links are on the chain and not fixed to the base, and
// solver::validate. Errors name the scene location of the offending entry; errors inside the
// URDF are reported at the scene's 'urdf' (or 'root'/'tip') entry with the URDF's own message.
model::Chain load_scene_chain(const Scene& scene);

// The scene used when there is no scene file (`--urdf --root --tip` only): namespace from the
// URDF file's stem (made an identifier: 'panda.urdf' -> panda, '7dof-arm.urdf' -> robot_7dof_arm);
// one torque instance "tau_ff"; one external force "f_ext_tip" on the tip link; Nc = 6 with
// run-time directions; every policy; decomposed (Alg. 2); scalars [double]; outputs only; default
// gravity and pivot tolerance. Loads the URDF to resolve an empty root/tip (so both are filled
// in); throws InputError if it cannot be loaded.
// `branch_tips` add tips (a tree; the constraint set stays on the first tip); snap_quarter_turns as ChainSpec's.
Scene default_scene(const std::string& urdf, const std::string& root = "", const std::string& tip = "",
                    const std::vector<std::string>& branch_tips = {}, bool snap_quarter_turns = true);

// Whether `name` is a usable C++ identifier (not a keyword, not reserved).
bool is_identifier(const std::string& name);

}  // namespace sweepgen::scene
