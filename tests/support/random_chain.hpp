// Random serial chains and trees built programmatically (no URDF), for tests over many
// kinematic and inertial configurations: 1..10 joints (trees 2..12, any branching), revolute about random unit axes or prismatic along
// them, random tree transforms, physically valid random inertias, rotor inertia on some joints,
// lumped link frames on some bodies and, on about half of the chains, a tip frame behind a
// (virtual) fixed joint.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>

#include "model/chain.hpp"

namespace sweepgen::test {

class RandomChainGenerator {
 public:
  explicit RandomChainGenerator(unsigned seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool chance(double p) { return uniform(0, 1) < p; }

  model::Vec3 unit_vector() {
    std::normal_distribution<double> normal;
    model::Vec3 v;
    do v = model::Vec3(normal(rng_), normal(rng_), normal(rng_));
    while (v.norm() < 1e-3);
    return v.normalized();
  }
  model::Mat3 rotation() {
    std::normal_distribution<double> normal;
    Eigen::Quaterniond quaternion(normal(rng_), normal(rng_), normal(rng_), normal(rng_));
    return quaternion.normalized().toRotationMatrix();
  }
  model::Transform transform(double offset) {
    model::Transform X;
    X.E = rotation();
    for (int k = 0; k < 3; ++k) X.r[k] = uniform(-offset, offset);
    return X;
  }

  // A rigid body: mass 0.1..5 kg, COM within 0.2 m of the origin, principal moments from a
  // random mass distribution (so they satisfy the triangle inequality), random principal axes.
  model::Inertia inertia(double& mass) {
    mass = uniform(0.1, 5.0);
    model::Vec3 com;
    for (int k = 0; k < 3; ++k) com[k] = uniform(-0.2, 0.2);
    // Second moments σ_k = m s_k^2 of the mass distribution; I_1 = σ_2 + σ_3 etc.
    model::Vec3 sigma;
    for (int k = 0; k < 3; ++k) sigma[k] = mass * std::pow(uniform(0.01, 0.2), 2);
    const model::Vec3 principal(sigma[1] + sigma[2], sigma[0] + sigma[2], sigma[0] + sigma[1]);
    const model::Mat3 R = rotation();
    const model::Mat3 inertia_com = R * principal.asDiagonal() * R.transpose();
    const model::Mat3 cx = spatial::skew(com);
    const model::Mat3 inertia_origin = inertia_com - mass * cx * cx;  // parallel axis theorem
    return model::Inertia::rigid(mass, mass * com, inertia_origin);
  }

  // A chain of `dof` joints (0: random 1..10).
  model::Chain chain(std::size_t dof = 0) {
    const std::size_t n = dof > 0 ? dof : static_cast<std::size_t>(std::uniform_int_distribution<int>(1, 10)(rng_));
    model::Chain c = base("random chain ");
    for (std::size_t i = 1; i <= n; ++i) add_body(c, i - 1);
    add_tip(c, n);
    return c;
  }

  // A tree of `dof` joints (0: random 2..12): body i hangs from a random earlier body, the base
  // included, so depth and branching vary from a chain to a star. Its tip is the last body's
  // link (or a frame behind it); every branch end is another tip.
  model::Chain tree(std::size_t dof = 0) {
    const std::size_t n = dof > 0 ? dof : static_cast<std::size_t>(std::uniform_int_distribution<int>(2, 12)(rng_));
    model::Chain c = base("random tree ");
    grow_tree(c, n);
    return c;
  }

  // A random tree of 1..10 joints on a floating base (F5) with a random root body: joints 1..6
  // are the base's coordinates, every further body hangs from the root body or a later one.
  model::Chain floating_tree(std::size_t dof = 0) {
    const std::size_t n = dof > 0 ? dof : static_cast<std::size_t>(std::uniform_int_distribution<int>(1, 10)(rng_));
    model::Chain c = base("random floating tree ");
    double mass = 0;
    const model::Inertia root = inertia(mass);
    model::add_floating_base(c, root, mass);
    grow_tree(c, n);
    return c;
  }

  std::mt19937_64& engine() { return rng_; }

 private:
  model::Chain base(const std::string& kind) {
    model::Chain c;
    c.source = kind + std::to_string(++count_);
    c.root_link = "base";
    c.bodies.push_back(model::Body{"base", {}, model::Inertia{}, 0});
    c.joints.push_back(model::Joint{});
    c.parent.push_back(0);
    c.frames["base"] = model::Frame{0, model::Transform::identity()};
    return c;
  }

  // `n` bodies after the chain's last, each on a random joint against a random one of the bodies
  // from that last one on; the tip is the last body's link (or a frame behind it), every other
  // branch end a further tip.
  void grow_tree(model::Chain& c, std::size_t n) {
    const std::size_t first = c.bodies.size(), last = first + n - 1;
    for (std::size_t i = first; i <= last; ++i)
      add_body(c, static_cast<std::size_t>(std::uniform_int_distribution<std::size_t>(first - 1, i - 1)(rng_)));
    add_tip(c, last);
    std::vector<bool> has_child(last + 1, false);
    for (std::size_t i = first; i <= last; ++i) has_child[c.parent[i]] = true;
    for (std::size_t i = first; i < last; ++i)
      if (!has_child[i]) c.branch_tips.push_back(c.bodies[i].link);
  }

  // Body i = c.dof() + 1 on a random joint against body `parent`.
  void add_body(model::Chain& c, std::size_t parent) {
    const std::size_t i = c.bodies.size();
    model::Joint j;
    j.name = "joint" + std::to_string(i);
    j.type = chance(0.25) ? model::JointType::prismatic : model::JointType::revolute;
    j.axis = unit_vector();
    j.tree_transform = transform(0.5);
    if (chance(0.3)) j.rotor_inertia = uniform(0.01, 0.5);
    j.effort_limit = uniform(5, 50);
    j.velocity_limit = 3;
    if (j.type == model::JointType::prismatic) {
      j.lower = -0.5;
      j.upper = 0.5;
    } else if (chance(0.5)) {
      j.continuous = true;  // unlimited: states drawn in [-pi, pi]
    } else {
      j.lower = -2.5;
      j.upper = 2.5;
    }
    c.joints.push_back(j);
    model::Body body;
    body.link = "link" + std::to_string(i);
    body.inertia = inertia(body.mass);
    c.frames[body.link] = model::Frame{i, model::Transform::identity()};
    // A massless link behind a fixed joint, addressable as a frame.
    if (chance(0.3)) {
      const std::string name = "frame" + std::to_string(i);
      body.lumped_links.push_back({name, 0.0, ""});
      c.frames[name] = model::Frame{i, transform(0.3)};
    }
    c.bodies.push_back(body);
    c.parent.push_back(parent);
  }

  // The tip: body n's link, or on half of the chains a frame behind it.
  void add_tip(model::Chain& c, std::size_t n) {
    c.tip_link = "link" + std::to_string(n);
    if (chance(0.5)) {
      c.tip_link = "tip";
      c.bodies[n].lumped_links.push_back({"tip", 0.0, ""});
      c.frames["tip"] = model::Frame{n, transform(0.3)};
    }
  }

  std::mt19937_64 rng_;
  unsigned count_ = 0;
};

}  // namespace sweepgen::test
