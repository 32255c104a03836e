#include "solver/flat_layout.hpp"

#include <stdexcept>

namespace sweepgen::solver {

namespace {

bool is_coupled(const std::vector<model::JointCoupling>& couplings, Eigen::Index at) {
  for (const model::JointCoupling& coupling : couplings)
    if (static_cast<Eigen::Index>(coupling.joint) == at + 1) return true;
  return false;
}

}  // namespace

std::vector<double> generated_positions(const JointVector<double>& q, const spatial::Mat3<double>& base_rotation,
                                        bool floating_base, const std::vector<model::JointCoupling>& couplings) {
  std::vector<double> generated;
  if (floating_base)
    for (Eigen::Index r = 0; r < 3; ++r)
      for (Eigen::Index c = 0; c < 3; ++c) generated.push_back(base_rotation(r, c));  // row-major
  for (Eigen::Index i = floating_base ? 6 : 0; i < q.size(); ++i)
    if (!is_coupled(couplings, i)) generated.push_back(q[i]);
  return generated;
}

std::vector<double> generated_velocities(const JointVector<double>& qd, const std::vector<model::JointCoupling>& couplings) {
  std::vector<double> generated;
  for (Eigen::Index i = 0; i < qd.size(); ++i)
    if (!is_coupled(couplings, i)) generated.push_back(qd[i]);
  return generated;
}

void follow_couplings(JointVector<double>& q, JointVector<double>& qd, const std::vector<model::JointCoupling>& couplings) {
  for (const model::JointCoupling& c : couplings) {
    const auto m = static_cast<Eigen::Index>(c.joint - 1), s = static_cast<Eigen::Index>(c.source - 1);
    q[m] = c.multiplier * q[s] + c.offset;
    qd[m] = c.multiplier * qd[s];
  }
}

std::vector<double> flat_input(const SolveInputs<double>& inputs, const FlatLayout& layout) {
  std::vector<double> flat;
  flat.reserve(layout.in_size());
  const auto append = [&flat](const auto& v) { flat.insert(flat.end(), v.data(), v.data() + v.size()); };
  const std::vector<double> q = generated_positions(inputs.q, inputs.base_rotation, layout.floating_base, layout.couplings);
  flat.insert(flat.end(), q.begin(), q.end());
  const std::vector<double> qd = generated_velocities(inputs.qd, layout.couplings);
  flat.insert(flat.end(), qd.begin(), qd.end());
  for (const auto& tau : inputs.torques) append(tau);
  for (const auto& w : inputs.wrenches) {
    append(w.moment);
    append(w.force);
  }
  for (std::size_t k : layout.input_directions) {
    append(inputs.alpha.at(k).moment);
    append(inputs.alpha.at(k).force);
  }
  append(inputs.beta);
  if (flat.size() != layout.in_size())
    throw std::logic_error("flat_input: " + std::to_string(flat.size()) + " values for a layout of " +
                           std::to_string(layout.in_size()));
  return flat;
}

SolveInputs<double> solve_inputs_from_flat(const double* in, const FlatLayout& flat, const DriverLayout& drivers) {
  SolveInputs<double> inputs;
  const auto n = static_cast<Eigen::Index>(flat.dof);
  const auto vector_at = [in](std::size_t offset, Eigen::Index size) {
    return JointVector<double>(Eigen::Map<const Eigen::VectorXd>(in + offset, size));
  };
  const auto force_at = [in](std::size_t offset) {
    return spatial::Force<double>{spatial::Vec3<double>(in[offset], in[offset + 1], in[offset + 2]),
                                  spatial::Vec3<double>(in[offset + 3], in[offset + 4], in[offset + 5])};
  };
  // q and q̇ as the generated code holds them (a floating base's rotation first, no coupled
  // joint), then each coupled joint's from its source (M1).
  inputs.q = JointVector<double>::Zero(n);
  inputs.qd = JointVector<double>::Zero(n);
  std::size_t position = flat.q() + (flat.floating_base ? 9 : 0), velocity = flat.qd();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (is_coupled(flat.couplings, i)) continue;
    if (!flat.floating_base || i >= 6) inputs.q[i] = in[position++];
    inputs.qd[i] = in[velocity++];
  }
  follow_couplings(inputs.q, inputs.qd, flat.couplings);
  if (flat.floating_base)
    for (Eigen::Index r = 0; r < 3; ++r)
      for (Eigen::Index c = 0; c < 3; ++c) inputs.base_rotation(r, c) = in[flat.q() + static_cast<std::size_t>(3 * r + c)];
  for (std::size_t t = 0; t < flat.torques; ++t) inputs.torques.push_back(vector_at(flat.torque(t), n));
  for (std::size_t e = 0; e < flat.external_forces; ++e) inputs.wrenches.push_back(force_at(flat.external_force(e)));
  std::size_t next_direction = 0;
  inputs.alpha = directions_with(drivers, [&] { return force_at(flat.alpha(next_direction++)); });
  inputs.beta = ConstraintVector<double>(Eigen::Map<const Eigen::VectorXd>(in + flat.beta(), static_cast<Eigen::Index>(flat.constraints)));
  return inputs;
}

}  // namespace sweepgen::solver
