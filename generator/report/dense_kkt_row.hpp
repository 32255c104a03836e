// `sweepgen report`'s "dense KKT" row: the oracle's dense KKT solve (oracle/dense_kkt.hpp) timed
// call by call on the scene's problems, its outcomes in the report's terms.
#pragma once

#include <vector>

#include "report/measure.hpp"

namespace sweepgen::report {

VariantResult measure_dense_kkt(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                                const TimingOptions& timing);

}  // namespace sweepgen::report
