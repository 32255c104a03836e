// `sweepgen report`: KDL 1.5's ChainHdSolver_Vereshchagin on the same states, when sweepgen
// was built with KDL and kdl_parser (SWEEPGEN_HAVE_KDL). Conventions translated as in
// tests/test_reference_kdl.cpp:
//  - the KDL chain runs from the root to the last *moving* link (KDL's solver cannot take
//    fixed joints), the links behind fixed joints after it and the branches off the chain
//    lumped into its segments' inertias (oracle/kdl_chain.hpp); fixed joints before it make the
//    scene inexpressible (the row says so). A tip behind
//    fixed joints is expressed on that link: alfa_k is tip().X^T alpha_k
//    (generator/spatial/spatial.hpp), and a wrench on a lumped link likewise through
//    frames[link].X;
//  - wrenches and alfa in base orientation, [force; moment]; root acceleration -g;
//    rotor inertia as KDL joint inertia; the torque instances summed into ff_torques;
//  - τcmd = τff + J^T(−alfa ν_KDL) (KDL's constraint_torques is τctrl), with KDL's own
//    Jacobian, computed outside the timed loop;
//  - Ẍ_tip from getTransformedLinkAcceleration (base orientation, about the last moving link's
//    origin) moved into the tip frame.
// Inputs in base orientation are prepared outside the timed loop (from the outward sweep's
// rotations); the timed loop is CartToJnt plus the getters for ν and the link accelerations.
#pragma once

#include "report/measure.hpp"

namespace sweepgen::report {

// The "kdl" row: measured, or with `note` saying why it is not (KDL not found at build time,
// kdl_parser cannot read the URDF, fixed joints between moving ones, ...).
VariantResult measure_kdl(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                          const TimingOptions& timing);

}  // namespace sweepgen::report
