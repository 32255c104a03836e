// The mimic mode `coupled` (docs/derivation.md, M1): each <mimic> joint the chain moves held to the
// root of the <mimic>s it follows, the numbers composed along the way.
#pragma once

#include <string>
#include <vector>

#include "model/chain.hpp"

namespace urdf {
class ModelInterface;
}

namespace sweepgen::model {

// The couplings of `chain`'s moving <mimic> joints, in joint order. Throws InputError (naming
// `urdf`, the joint's <mimic> and `mode_location`, where the mode was asked for) where the root
// source is not a moving joint of the chain (fixed, locked, or on no path to a tip) or a <mimic> on
// the way follows a joint the URDF does not have. Cycles are refused before (refuse_mimic_cycles).
std::vector<JointCoupling> mimic_couplings(const urdf::ModelInterface& model, const Chain& chain, const std::string& urdf,
                                           const std::string& mode_location);

}  // namespace sweepgen::model
