// The condition numbers in binary128, the referee's scalar, and in long double (the report's cond(M),
// report/measure.cpp; the tests), compiled once for the report and the tests
// (condition_number_definitions.hpp).
#include "oracle/condition_number_definitions.hpp"
#include "solver/quad_scalar.hpp"

namespace sweepgen::oracle {

template double condition_number_of<solver::Quad>(const DenseMatrix<solver::Quad>&);
template double scaled_condition_number_of<solver::Quad>(const DenseMatrix<solver::Quad>&);
template double condition_number_of<long double>(const DenseMatrix<long double>&);
template double scaled_condition_number_of<long double>(const DenseMatrix<long double>&);

}  // namespace sweepgen::oracle
