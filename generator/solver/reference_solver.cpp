// The reference solver's sweeps for double and float, compiled once (reference_solver.hpp); long
// double, which only the tests run, in reference_solver_long_double.cpp.
#include "solver/reference_solver.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<double>;
template class ReferenceSolver<float>;

}  // namespace sweepgen::solver
