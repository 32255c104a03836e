// ReferenceSolver<Quad>, the referee's one instantiation (quad_scalar.hpp), in sweepgen_measure.
#include "solver/quad_scalar.hpp"

namespace sweepgen::solver {

template class ReferenceSolver<Quad>;

}  // namespace sweepgen::solver
