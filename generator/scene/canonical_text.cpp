#include "scene/canonical_text.hpp"

#include <charconv>

namespace sweepgen::scene {
namespace {

// One labelled line per item; values unambiguous (a name's length before it, a number's shortest
// round-trip form), so that two different models never have the same text.
class CanonicalText {
 public:
  template <class... Values>
  void line(const char* label, const Values&... values) {
    text_ += label;
    (put(values), ...);
    text_ += '\n';
  }
  const std::string& text() const { return text_; }

 private:
  void put(const std::string& name) { text_ += ' ' + std::to_string(name.size()) + ':' + name; }
  void put(double value) {
    char digits[32];
    text_ += ' ';
    text_.append(digits, std::to_chars(digits, digits + sizeof digits, value).ptr);
  }
  void put(std::size_t count) { text_ += ' ' + std::to_string(count); }
  void put(bool flag) { text_ += flag ? " 1" : " 0"; }
  template <class Derived>
  void put(const Eigen::MatrixBase<Derived>& matrix) {
    for (Eigen::Index i = 0; i < matrix.rows(); ++i)
      for (Eigen::Index j = 0; j < matrix.cols(); ++j) put(static_cast<double>(matrix(i, j)));
  }
  template <class Item>
  void put(const std::vector<Item>& items) {
    put(items.size());
    for (const Item& item : items) put(item);
  }

  std::string text_;
};

void add_chain(CanonicalText& out, const model::Chain& chain) {
  out.line("chain", chain.root_link, chain.tip_link, chain.branch_tips, chain.floating_base, chain.exact_quarter_turns);
  for (std::size_t i = 0; i < chain.bodies.size(); ++i) {
    const model::Body& b = chain.bodies[i];
    out.line("body", b.link, b.mass, b.inertia.A, b.inertia.B, b.inertia.C, chain.parent[i]);
    for (const model::LumpedLink& l : b.lumped_links) out.line(" lumped", l.link, l.mass, l.locked_joint);
    const model::Joint& j = chain.joints[i];
    out.line(" joint", j.name, j.type == model::JointType::prismatic, j.continuous, j.axis, j.tree_transform.E,
             j.tree_transform.r, j.rotor_inertia, j.effort_limit, j.velocity_limit, j.lower, j.upper,
             j.floating_base_coordinate);
  }
  for (const auto& [link, frame] : chain.frames) out.line("frame", link, frame.body, frame.X.E, frame.X.r);
  for (const model::LockedJoint& l : chain.locked_joints) out.line("locked", l.name, l.body, l.position, l.from_scene);
  for (const model::LeftOutLink& l : chain.left_out) out.line("left_out", l.link, l.mass, l.reason);
  for (const model::UnmodelledDynamics& d : chain.unmodelled_dynamics) out.line("dynamics", d.joint, d.damping, d.friction);
  for (const model::MimicJoint& m : chain.mimics) out.line("mimic", m.joint, m.source, m.multiplier, m.offset);
  for (const model::JointCoupling& c : chain.couplings) out.line("coupling", c.joint, c.source, c.multiplier, c.offset);
  for (const model::ModelChange& c : chain.changes) out.line("change", c.element, c.written, c.taken_as, c.deviation, c.unit);
}

void add_scene(CanonicalText& out, const Scene& s) {
  out.line("solver", s.solver, s.gravity, s.expose_all, s.check_inputs, s.refinement, s.pivot_tolerance);
  const solver::DriverLayout& layout = s.layout;
  out.line("torques", layout.torques);
  for (const solver::ExternalForceDriver& f : layout.external_forces) out.line("external_force", f.name, f.link);
  out.line("constraints", layout.constraints);
  for (const solver::ConstraintSet& set : layout.sets) {
    out.line("set", set.link, set.count);
    if (set.at.E != model::Mat3::Identity() || set.at.r != model::Vec3::Zero()) out.line(" at", set.at.E, set.at.r);
    if (set.relative()) out.line(" relative_to", set.relative_to, set.relative_at.E, set.relative_at.r);
    for (const spatial::Force<double>& direction : set.fixed) out.line(" direction", direction.moment, direction.force);
  }
  for (const solver::Track& t : layout.tracks) out.line("track", t.name, t.bias, t.torques, t.external_forces);
  for (const solver::Policy policy : s.policies) out.line("policy", std::string(solver::name(policy)));
  out.line("scalars", s.scalars);
  out.line("factorisation", s.constraint_factorisation == solver::ConstraintFactorisation::damped);
  out.line("constraint_rows", s.constraint_rows.has_value(),
           s.constraint_rows == solver::ConstraintRows::outward_rows);
  const solver::SolveOutputs& o = s.outputs;
  out.line("outputs", o.qdd, o.tau_cmd, o.tau_ctrl, o.nu, o.tip_acceleration, o.set_acceleration, o.closure_error);
  const solver::DerivativeOutputs& d = s.derivative_outputs;
  out.line("derivatives", s.derivatives, d.qdd, d.nu, d.tau_cmd);
}

}  // namespace

std::string canonical_text(const Scene& scene, const model::Chain& chain) {
  CanonicalText out;
  add_chain(out, chain);
  add_scene(out, scene);
  return out.text();
}

}  // namespace sweepgen::scene
