// The dense oracle compiled once for double (the report's dense-KKT row, bench/) and long double
// (the tests' oracle) instead of in every file that includes it.
#include "oracle/dense_dynamics.hpp"

namespace sweepgen::oracle {

template class DenseDynamics<double>;
template class DenseDynamics<long double>;

}  // namespace sweepgen::oracle
