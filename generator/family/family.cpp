#include "family/family.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>

#include "model/error.hpp"

namespace sweepgen::family {
namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kHalfPi = 1.5707963267948966;
constexpr double kGravity = 9.81;

// Uniform numbers from mt19937_64 (its output sequence is fixed by the standard; the
// standard's distributions are not, so the mapping is ours: 53 random bits).
class Stream {
 public:
  explicit Stream(std::uint64_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1p-53); }
  // A unit vector, uniform on the sphere (rejection from the cube; sqrt only).
  Vec3 unit_vector() {
    for (;;) {
      const Vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
      const double n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      if (n2 > 1e-4 && n2 <= 1) {
        const double n = std::sqrt(n2);
        return {v[0] / n, v[1] / n, v[2] / n};
      }
    }
  }
  // A uniformly random rotation, from a unit quaternion (rejection from the 4-cube).
  std::array<Vec3, 3> rotation() {
    for (;;) {
      double w = uniform(-1, 1), x = uniform(-1, 1), y = uniform(-1, 1), z = uniform(-1, 1);
      const double n2 = w * w + x * x + y * y + z * z;
      if (!(n2 > 1e-4 && n2 <= 1)) continue;
      const double n = std::sqrt(n2);
      w /= n, x /= n, y /= n, z /= n;
      return {Vec3{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
              Vec3{2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
              Vec3{2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    }
  }

 private:
  std::mt19937_64 rng_;
};

// Tensor Q diag(p) Q^T as (ixx, ixy, ixz, iyy, iyz, izz).
std::array<double, 6> rotated_tensor(const std::array<Vec3, 3>& Q, const Vec3& p) {
  const auto e = [&](int a, int b) { return Q[a][0] * p[0] * Q[b][0] + Q[a][1] * p[1] * Q[b][1] + Q[a][2] * p[2] * Q[b][2]; };
  return {e(0, 0), e(0, 1), e(0, 2), e(1, 1), e(1, 2), e(2, 2)};
}

// Principal moments of a mass distribution with second moments sigma (I_x = σ_y + σ_z, ...):
// any such triple satisfies the triangle inequalities, with equality when a σ is 0.
Vec3 principal_moments(const Vec3& sigma) {
  return {sigma[1] + sigma[2], sigma[0] + sigma[2], sigma[0] + sigma[1]};
}

// A generic link: mass m, a solid of length l (along z) and radius 0.1 l_ref, COM near the
// middle, full tensor in a randomly rotated inertial frame.
LinkSpec generic_link(const std::string& name, double m, double l, double l_ref, Stream& random) {
  LinkSpec link;
  link.name = name;
  link.mass = m;
  const double radius = 0.1 * l_ref;
  link.com = {random.uniform(-0.05, 0.05) * l_ref, random.uniform(-0.05, 0.05) * l_ref, l / 2};
  link.com_rpy = {random.uniform(-kPi, kPi), random.uniform(-kHalfPi, kHalfPi), random.uniform(-kPi, kPi)};
  link.inertia = rotated_tensor(random.rotation(), principal_moments({m * radius * radius / 4, m * radius * radius / 4, m * l * l / 12}));
  return link;
}

// A thin rod of radius `radius` (0: the limit) from the link origin along link z. The
// inertial frame is turned by rpy (π/2, 0, 0) (taken exactly by the loader), so that the
// rod's axis is the inertial y axis: I_yy = m r²/2 about the axis, I_xx = I_zz = m(3r² + l²)/12.
LinkSpec rod_link(const std::string& name, double m, double l, double radius) {
  LinkSpec link;
  link.name = name;
  link.mass = m;
  link.com = {0, 0, l / 2};
  link.com_rpy = {kHalfPi, 0, 0};
  const double across = m * (3 * radius * radius + l * l) / 12;
  link.inertia = {across, 0, 0, m * radius * radius / 2, 0, across};
  return link;
}

// A flat disc of radius R at the middle of the link, its normal along link x (inertial frame
// turned by rpy (0, π/2, 0)): I_xx = I_yy = m R²/4, I_zz = 2 I_xx exactly (triangle equality).
LinkSpec disc_link(const std::string& name, double m, double l, double R) {
  LinkSpec link;
  link.name = name;
  link.mass = m;
  link.com = {0, 0, l / 2};
  link.com_rpy = {0, kHalfPi, 0};
  const double in_plane = m * R * R / 4;
  link.inertia = {in_plane, 0, 0, in_plane, 0, 2 * in_plane};
  return link;
}

// Effort limit: the static torque of everything outboard held out at full reach, twice.
void set_limits(RobotSpec& robot, double reach) {
  double outboard = 0;
  for (std::size_t i = robot.joints.size(); i >= 1; --i) {
    outboard += robot.links[i].has_inertial ? robot.links[i].mass : 0;
    JointSpec& j = robot.joints[i - 1];
    if (j.kind == JointKind::prismatic) {
      j.lower = -0.3 * reach / static_cast<double>(robot.joints.size());
      j.upper = -j.lower;
      j.effort = 2 * kGravity * outboard;
      j.velocity = reach / static_cast<double>(robot.joints.size());
    } else {
      j.lower = -2.9;
      j.upper = 2.9;
      j.effort = 2 * kGravity * outboard * reach;
      j.velocity = 3;
    }
  }
}

// The 6-joint arm every arm case starts from, in units of its link length l [m] and mass m
// [kg]. Joints: base yaw (z), shoulder (y), elbow (y), wrist roll (z), wrist pitch (y),
// flange roll (z), with offsets along z: at q = 0 the arm is stretched straight up and the
// wrist roll and flange roll axes are one line (both singular for 6 tip constraints).
constexpr std::array<double, 6> kArmOffsets{0.75, 0.25, 1.0, 1.0, 0.25, 0.25};
constexpr std::array<char, 6> kArmAxes{'z', 'y', 'y', 'z', 'y', 'z'};
constexpr std::array<double, 6> kArmMasses{1.5, 1.2, 1.0, 0.6, 0.4, 0.2};

Vec3 frame_axis(char a) { return a == 'x' ? Vec3{1, 0, 0} : a == 'y' ? Vec3{0, 1, 0} : Vec3{0, 0, 1}; }
double link_length(std::size_t i) { return i + 1 < kArmOffsets.size() ? kArmOffsets[i + 1] : 0.25; }

RobotSpec arm(const std::string& name, double l, double m, const std::array<double, 6>& masses = kArmMasses) {
  Stream random(6);  // the same geometry at every scale
  RobotSpec robot;
  robot.name = name;
  robot.links.push_back({"base", false});
  for (std::size_t i = 0; i < 6; ++i) {
    JointSpec j;
    j.name = "joint" + std::to_string(i + 1);
    j.xyz = {0, 0, kArmOffsets[i] * l};
    j.axis = frame_axis(kArmAxes[i]);
    robot.joints.push_back(j);
    robot.links.push_back(generic_link("link" + std::to_string(i + 1), masses[i] * m,
                                       link_length(i) * l, l, random));
  }
  set_limits(robot, 3.5 * l);
  return robot;
}

FamilyCase arm_case(const std::string& name, const std::string& purpose, RobotSpec robot, double l, double m) {
  FamilyCase c;
  c.name = name;
  c.purpose = purpose;
  c.robot = std::move(robot);
  c.tip = "link6";
  c.force_link = "link3";
  c.length_scale = l;
  c.mass_scale = m;
  c.singular_q.assign(6, 0.0);
  return c;
}

// A long chain of n joints: revolute, continuous and prismatic about random unit axes, random
// tree transforms, 0.2..2 kg links with full tensors in rotated inertial frames.
FamilyCase long_chain(std::size_t n) {
  Stream random(1000 + n);
  FamilyCase c;
  c.name = "chain_" + std::to_string(n);
  c.purpose = std::to_string(n) + " joints (revolute, continuous, prismatic about random axes), full inertia tensors in "
              "rotated inertial frames: rounding accumulated over a long recursion; conservative RK4 energy drift";
  c.robot.name = c.name;
  c.robot.links.push_back({"base", false});
  const double l = 0.1;
  for (std::size_t i = 0; i < n; ++i) {
    JointSpec j;
    j.name = "joint" + std::to_string(i + 1);
    const double kind = random.uniform(0, 1);
    j.kind = kind < 0.5 ? JointKind::revolute : kind < 0.75 ? JointKind::continuous : JointKind::prismatic;
    j.axis = random.unit_vector();
    j.xyz = {random.uniform(-0.3, 0.3) * l, random.uniform(-0.3, 0.3) * l, random.uniform(0.5, 1.5) * l};
    j.rpy = {random.uniform(-0.5, 0.5), random.uniform(-0.5, 0.5), random.uniform(-0.5, 0.5)};
    c.robot.joints.push_back(j);
    LinkSpec link;
    link.name = "link" + std::to_string(i + 1);
    link.mass = random.uniform(0.2, 2.0);
    link.com = {random.uniform(-0.5, 0.5) * l, random.uniform(-0.5, 0.5) * l, random.uniform(0, 1) * l};
    link.com_rpy = {random.uniform(-kPi, kPi), random.uniform(-kHalfPi, kHalfPi), random.uniform(-kPi, kPi)};
    Vec3 sigma;
    for (double& s : sigma) s = link.mass * std::pow(random.uniform(0.05, 0.5) * l, 2);
    link.inertia = rotated_tensor(random.rotation(), principal_moments(sigma));
    c.robot.links.push_back(link);
  }
  set_limits(c.robot, static_cast<double>(n) * l);
  c.tip = "link" + std::to_string(n);
  c.force_link = "link" + std::to_string(n / 2);
  c.length_scale = l;
  c.mass_scale = 1;
  c.heavy = n >= 100;
  return c;
}

using Maker = std::function<FamilyCase()>;

const std::vector<std::pair<std::string, Maker>>& makers() {
  static const std::vector<std::pair<std::string, Maker>> list = {
      {"arm", [] { return arm_case("arm", "the 6-joint arm every arm case derives from: 0.4 m links, 0.4..3 kg", arm("arm", 0.4, 2), 0.4, 2); }},
      {"arm_micro", [] {
         return arm_case("arm_micro", "the same arm with 1e-4 m links and 1e-3 kg masses (inertias ~1e-11 kg m^2)",
                         arm("arm_micro", 1e-4, 1e-3), 1e-4, 1e-3);
       }},
      {"arm_giant", [] {
         return arm_case("arm_giant", "the same arm with 50 m links and 1e4 kg masses (inertias ~1e7 kg m^2)",
                         arm("arm_giant", 50, 1e4), 50, 1e4);
       }},
      {"mass_ratio_alternating", [] {
         return arm_case("mass_ratio_alternating", "consecutive link masses alternate by 1e6 (ratios 1e6 and 1e-6)",
                         arm("mass_ratio_alternating", 0.4, 1, {1, 1e6, 1, 1e6, 1, 1e6}), 0.4, 1);
       }},
      {"mass_ratio_light_tool", [] {
         return arm_case("mass_ratio_light_tool", "a light tool on a heavy arm: last link 1e-6 of the one before",
                         arm("mass_ratio_light_tool", 0.4, 10, {1.5, 1.2, 1.0, 0.6, 0.4, 0.4e-6}), 0.4, 10);
       }},
      {"mass_ratio_heavy_tool", [] {
         return arm_case("mass_ratio_heavy_tool", "a heavy payload on a light arm: last link 1e6 times the one before",
                         arm("mass_ratio_heavy_tool", 0.4, 1, {1.5, 1.2, 1.0, 0.6, 0.4, 0.4e6}), 0.4, 1);
       }},
      {"thin_rods", [] {
         RobotSpec robot = arm("thin_rods", 0.4, 2);
         for (std::size_t i = 1; i <= 6; ++i) {
           const double l = link_length(i - 1) * 0.4;
           // The last joint spins its rod about the rod's own axis: D_6 = m r²/2 with r = 1e-5 l.
           robot.links[i] = rod_link(robot.links[i].name, robot.links[i].mass, l, i == 6 ? 1e-5 * l : 0.0);
         }
         return arm_case("thin_rods",
                         "every link a thin rod at the triangle-inequality limit (I_axial = 0); the last joint spins a "
                         "rod of radius 1e-5 l about its own axis (D_6 / trace ~ 1e-10)",
                         robot, 0.4, 2);
       }},
      {"flat_discs", [] {
         RobotSpec robot = arm("flat_discs", 0.4, 2);
         for (std::size_t i = 1; i <= 6; ++i)
           robot.links[i] = disc_link(robot.links[i].name, robot.links[i].mass, link_length(i - 1) * 0.4, 0.1);
         return arm_case("flat_discs", "every link a flat disc at the triangle-inequality limit (I1 + I2 = I3)", robot, 0.4, 2);
       }},
      {"massless_links", [] {
         RobotSpec robot = arm("massless_links", 0.4, 2);
         robot.links[2].has_inertial = false;
         robot.links[4].has_inertial = false;
         return arm_case("massless_links", "links 2 and 4 without <inertial> in mid-chain", robot, 0.4, 2);
       }},
      {"skew_axes", [] {
         RobotSpec robot = arm("skew_axes", 0.4, 2);
         Stream random(7);
         const JointKind kinds[6] = {JointKind::revolute, JointKind::revolute,   JointKind::prismatic,
                                     JointKind::revolute, JointKind::continuous, JointKind::revolute};
         for (std::size_t i = 0; i < 6; ++i) {
           robot.joints[i].kind = kinds[i];
           robot.joints[i].axis = random.unit_vector();
         }
         set_limits(robot, 3.5 * 0.4);
         FamilyCase c = arm_case("skew_axes", "joint axes that are no frame axis (random unit vectors), one prismatic and "
                                 "one continuous joint", robot, 0.4, 2);
         c.singular_q.clear();
         return c;
       }},
      {"coaxial_massless", [] {
         RobotSpec robot = arm("coaxial_massless", 0.4, 2);
         robot.joints[4].axis = {0, 0, 1};  // joint 5 about z at link 4's origin: coaxial with joint 4
         robot.joints[4].xyz = {0, 0, 0};
         robot.links[4].has_inertial = false;
         return arm_case("coaxial_massless",
                         "joints 4 and 5 coaxial with the massless link 4 between: M(q) is singular (D_4 = 0 in exact "
                         "arithmetic), the joint-inertia policy's case",
                         robot, 0.4, 2);
       }},
      {"chain_30", [] { return long_chain(30); }},
      {"chain_100", [] { return long_chain(100); }},
      {"chain_300", [] { return long_chain(300); }},
  };
  return list;
}

}  // namespace

const std::vector<std::string>& family_case_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [name, make] : makers()) n.push_back(name);
    return n;
  }();
  return names;
}

FamilyCase family_case(const std::string& name) {
  for (const auto& [case_name, make] : makers())
    if (case_name == name) return make();
  throw InputError("sweepgen family", "case " + quote_name(name),
                   "no such case (see --list)" + nearest_name_hint(name, family_case_names()));
}

std::string scene_text(const FamilyCase& c) {
  return "# Written by `sweepgen family` (robots/family/README.md): " + c.purpose +
         "\nsweepgen_scene: 1\nsolver: family_" + c.name + "\nurdf: " + c.name + ".urdf\nroot: base\ntip: " + c.tip +
         "\ndrivers:\n  torques: [tau_ff]\n  external_forces:\n    - {name: f_tip, link: " + c.tip +
         "}\n    - {name: f_mid, link: " + c.force_link +
         "}\n  constraints: 6\ndecomposition: decomposed\npolicies: [original]\nscalars: [double, float]\n";
}

}  // namespace sweepgen::family
