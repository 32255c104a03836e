// The condition numbers in binary128, the referee's scalar, compiled once for the report and the
// tests (condition_number_definitions.hpp).
#include "oracle/condition_number_definitions.hpp"
#include "solver/quad_scalar.hpp"

namespace sweepgen::oracle {

template double condition_number_of<solver::Quad>(const DenseMatrix<solver::Quad>&);
template double scaled_condition_number_of<solver::Quad>(const DenseMatrix<solver::Quad>&);

}  // namespace sweepgen::oracle
