// The reference solver's sweeps for double, float and long double, compiled once
// (reference_solver.hpp).
#include "solver/reference_solver.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<double>;
template class ReferenceSolver<float>;
template class ReferenceSolver<long double>;

}  // namespace sweepgen::solver
