// The reference solver's sweeps for the dual scalar over double and DerivativeSolver<double>,
// compiled once (solve_derivatives.hpp): the derivatives of every solve, (D1).
#include "solver/solve_derivatives.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<Dual<double>>;
template class DerivativeSolver<double>;

}  // namespace sweepgen::solver
