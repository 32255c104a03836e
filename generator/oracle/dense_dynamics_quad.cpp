// DenseDynamics<Quad> (binary128), compiled once for the tests (dense_dynamics_definitions.hpp): the
// independent dense solve the closed-chain tests hold the binary128 reference solver to.
#include "oracle/dense_dynamics_definitions.hpp"
#include "solver/quad_scalar.hpp"

namespace sweepgen::oracle {

template class DenseDynamics<solver::Quad>;

}  // namespace sweepgen::oracle
