// The SVD behind the condition numbers compiled once for double and long double instead of in
// every file that asks for one.
#include "oracle/condition_number.hpp"

namespace sweepgen::oracle {

template double dense_condition_number<double>(const Eigen::MatrixXd&);
template double dense_condition_number<long double>(const Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>&);

}  // namespace sweepgen::oracle
