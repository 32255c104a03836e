#include "solver/flat_layout.hpp"

#include <stdexcept>

namespace sweepgen::solver {

namespace {

bool is_coupled(const std::vector<model::JointCoupling>& couplings, Eigen::Index at) {
  return model::coupling_of(couplings, static_cast<std::size_t>(at) + 1) != nullptr;
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

void joint_values_from_generated(const double* positions, const double* velocities, std::size_t dof, bool floating_base,
                                 const std::vector<model::JointCoupling>& couplings, JointVector<double>& q,
                                 JointVector<double>& qd) {
  q = JointVector<double>::Zero(static_cast<Eigen::Index>(dof));
  qd = JointVector<double>::Zero(static_cast<Eigen::Index>(dof));
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    if (is_coupled(couplings, i)) continue;
    if (!floating_base || i >= 6) q[i] = *positions++;
    qd[i] = *velocities++;
  }
  follow_couplings(q, qd, couplings);
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
  joint_values_from_generated(in + flat.q() + (flat.floating_base ? 9 : 0), in + flat.qd(), flat.dof, flat.floating_base,
                              flat.couplings, inputs.q, inputs.qd);
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
