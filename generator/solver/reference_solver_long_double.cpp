// The reference solver's sweeps for long double, compiled once for the tests (reference_solver.hpp).
#include "solver/reference_solver.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<long double>;

}  // namespace sweepgen::solver
