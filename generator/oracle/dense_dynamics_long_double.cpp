// DenseDynamics<long double>, compiled once for the tests (dense_dynamics_definitions.hpp).
#include "oracle/dense_dynamics_definitions.hpp"

namespace sweepgen::oracle {

template class DenseDynamics<long double>;

}  // namespace sweepgen::oracle
