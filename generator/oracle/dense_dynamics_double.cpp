// DenseDynamics<double>, compiled once for the report, the tests and bench/ (dense_dynamics_definitions.hpp).
#include "oracle/dense_dynamics_definitions.hpp"

namespace sweepgen::oracle {

template class DenseDynamics<double>;

}  // namespace sweepgen::oracle
