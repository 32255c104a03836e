// The KDL chain an oracle compares sweepgen's chain with, read by KDL's own loader (kdl_parser):
// root -> last *moving* link (KDL's Vereshchagin solver cannot take fixed joints), with the links
// behind fixed joints after it, and every branch that leaves the chain (fixed side links, and
// links behind moving joints held where model::Chain::locked_joints holds them), lumped into the
// segments' inertias through KDL's own frames and inertias; rotor inertia as KDL joint inertia.
// Shared by `sweepgen report` (report/kdl_row.cpp) and tests/test_reference_kdl.cpp. Only
// with KDL (SWEEPGEN_HAVE_KDL).
#pragma once

#ifdef SWEEPGEN_HAVE_KDL

#include <kdl/chain.hpp>
#include <string>

#include "model/chain.hpp"

namespace sweepgen::oracle {

// false, with the reason in `why`, when KDL cannot read `urdf` or its chain is not `chain`'s
// (fixed joints between moving ones, other bodies).
bool kdl_chain(const std::string& urdf, const model::Chain& chain, KDL::Chain& out, std::string& why);

}  // namespace sweepgen::oracle

#endif  // SWEEPGEN_HAVE_KDL
