// The condition numbers in double, compiled once for the tests
// (condition_number_definitions.hpp).
#include "oracle/condition_number_definitions.hpp"

namespace sweepgen::oracle {

template double condition_number_of<double>(const DenseMatrix<double>&);
template double scaled_condition_number_of<double>(const DenseMatrix<double>&);

}  // namespace sweepgen::oracle
