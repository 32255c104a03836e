// The reference solver's sweeps for double and float, compiled once (reference_solver.hpp).
#include "solver/reference_solver.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<double>;
template class ReferenceSolver<float>;

}  // namespace sweepgen::solver
