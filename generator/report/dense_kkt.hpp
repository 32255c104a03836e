// `sweepgen report`'s "dense KKT" row: the textbook alternative to a recursive solver. M(q),
// b(q, q̇) and the tip Jacobian from Newton–Euler (report/dense_dynamics.hpp, which shares no
// code with generator/solver), then the (n + Nc) saddle-point system of Gauss' principle,
//   [ M   −Jcᵀ ] [q̈]   [ τ + Σ J_iᵀ F_ext,i − b ]
//   [ Jc    0  ] [ν] = [ β − αᵀ c               ],   Jc = αᵀ J_tip,
// solved by Eigen's full-pivot LU, in double. It solves the original policy's problem with every
// direction kept: where the directions are dependent the system is singular and so is its answer
// (no pivot policy drops a direction).
#pragma once

#include "report/measure.hpp"

namespace sweepgen::report {

VariantResult measure_dense_kkt(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                                const TimingOptions& timing);

}  // namespace sweepgen::report
