// Textbook mechanisms with exact answers, through the reference solver in binary128, double and
// float: a pendulum, a double pendulum, a cart-pole, a body falling along a prismatic joint, an
// arm held still by a six-direction tip constraint, and a body spun about a principal axis.
// Each robot is a URDF written here and read by the project's loader; each answer is the
// textbook one (Lagrange's equations, statics), written out below and evaluated in binary128
// from the same numbers. Every case runs under every policy, with the drivers composed (Alg. 1)
// and decomposed (Alg. 2), a zero wrench on the tip as the external-force driver; no torque
// comes near the effort limits (1000), so the saturating policies clamp nothing and all four
// policies must give the textbook answer.
//
// Tolerance. A closed form is evaluated as Terms: its value and its size, the same expression
// on absolute values, so that any evaluation of it with a few roundings per operation errs by at
// most c·eps·size (the forward bound of sums of products: Higham, "Accuracy and Stability of
// Numerical Algorithms", 2002, §3.1). A linear solve x = A⁻¹ b (x / y the 1 x 1 one) gets
// Oettli–Prager's componentwise size |A⁻¹| (size b + size A |x|) (Higham §7.2): how far x moves
// when every entry of A and b moves by eps of its size, which a backward-stable solve may do.
// The solver computes the same physics along another path (the articulated-body recursion)
// through intermediate terms of the same sizes up to O(1) factors, so every result must lie
// within kUlps·eps·size of the value, eps its scalar's. Measured: the largest error over all
// cases, states, policies, layouts and scalars is 0.60 eps·size (the pendulum in float; the
// lines printed below); kUlps = 4 leaves a margin of 6. In binary128 the bound, 4 · 1.9e-34 ·
// size, checks the equations themselves: a wrong or missing term errs by far more. Absolute
// ceiling: every size here is at most kLargestSize (asserted); the largest, 2.1e4 rad/s², is the
// held arm's q̈ (the generalized forces that cancel there, through M⁻¹, large for its light last
// link); so no tolerance exceeds 4 · eps · 3e4 (2.7e-11 in double).
// The model numbers are dyadic with few significant bits, so that the loader's (F3) arithmetic
// and the cast to float are exact; each scalar's closed form takes the numbers as that scalar
// sees them (q, gravity and the spin case's rotated tensor rounded to it).
#include <gtest/gtest.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "model/urdf_loader.hpp"
#include "solver/quad_scalar.hpp"
#include "solver/reference_solver.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::Policy;
using solver::Quad;

constexpr double kGravity = 9.81;  // [m/s²], along −z of the base
constexpr double kUlps = 4;
constexpr double kLargestSize = 3e4;  // [rad/s², m/s², N, N m]
constexpr Policy kPolicies[] = {Policy::original, Policy::prioritize_external, Policy::saturate,
                                Policy::saturate_exact};

// ---- Closed forms with the size of their terms ---------------------------------------------

struct Term {
  Quad value, size;
};
Term term(const Quad& x) { return {x, abs(x)}; }
Term operator+(const Term& a, const Term& b) { return {a.value + b.value, a.size + b.size}; }
Term operator-(const Term& a, const Term& b) { return {a.value - b.value, a.size + b.size}; }
Term operator*(const Term& a, const Term& b) { return {a.value * b.value, a.size * b.size}; }
Term operator/(const Term& a, const Term& b) {
  const Quad quotient = a.value / b.value;
  return {quotient, (a.size + abs(quotient) * b.size) / abs(b.value)};
}

// A rotation about the base's y axis, the axis of every planar joint here: R_y(θ) takes a
// child-frame vector to the parent frame (F2 with a = e_y: E_J = R_y(q)ᵀ).
struct Angle {
  Term cos, sin;
};
Angle angle(const Quad& q) { return {term(cos(q)), term(sin(q))}; }
// θ1 + θ2 as the solver composes the rotations: the size keeps both products of each sum.
Angle operator+(const Angle& a, const Angle& b) {
  return {a.cos * b.cos - a.sin * b.sin, a.sin * b.cos + a.cos * b.sin};
}

// A vector in the base's x-z plane.
struct Planar {
  Term x, z;
};
Planar operator+(const Planar& a, const Planar& b) { return {a.x + b.x, a.z + b.z}; }
Planar operator-(const Planar& a, const Planar& b) { return {a.x - b.x, a.z - b.z}; }
Planar rotated(const Angle& t, const Planar& v) { return {t.cos * v.x + t.sin * v.z, t.cos * v.z - t.sin * v.x}; }

template <std::size_t N>
using TermVector = std::array<Term, N>;
template <std::size_t N>
using TermMatrix = std::array<TermVector<N>, N>;

// x = A⁻¹ b with Oettli–Prager's size |A⁻¹| (size b + size A |x|) (see the top; x / y above is
// the case N = 1).
template <std::size_t N>
TermVector<N> solve(const TermMatrix<N>& A, const TermVector<N>& b) {
  using Matrix = Eigen::Matrix<Quad, int(N), int(N)>;
  using Vector = Eigen::Matrix<Quad, int(N), 1>;
  Matrix value, size;
  Vector rhs, rhs_size;
  for (std::size_t r = 0; r < N; ++r) {
    for (std::size_t c = 0; c < N; ++c) value(r, c) = A[r][c].value, size(r, c) = A[r][c].size;
    rhs[r] = b[r].value, rhs_size[r] = b[r].size;
  }
  const Matrix inverse = value.inverse();
  const Vector x = inverse * rhs;
  const Vector x_size = inverse.cwiseAbs() * (rhs_size + size * x.cwiseAbs());
  TermVector<N> solution;
  for (std::size_t i = 0; i < N; ++i) solution[i] = {x[i], x_size[i]};
  return solution;
}
template <std::size_t N>
TermMatrix<N> transposed(const TermMatrix<N>& A) {
  TermMatrix<N> T;
  for (std::size_t r = 0; r < N; ++r)
    for (std::size_t c = 0; c < N; ++c) T[r][c] = A[c][r];
  return T;
}
template <std::size_t N>
TermVector<N> times(const TermMatrix<N>& A, const TermVector<N>& x) {
  TermVector<N> y;
  for (std::size_t r = 0; r < N; ++r)
    for (std::size_t c = 0; c < N; ++c) y[r] = y[r] + A[r][c] * x[c];
  return y;
}
Term dot(const TermVector<3>& a, const TermVector<3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
TermVector<3> cross(const TermVector<3>& a, const TermVector<3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// ---- The cases -----------------------------------------------------------------------------

// One state, in double; each scalar's solver gets it rounded to its scalar.
struct State {
  std::vector<double> q, qd, tau;
};
// The rounded state, exactly, in binary128.
struct Inputs {
  std::vector<Quad> q, qd, tau;
};
// A model number as the solver of one scalar sees it (rounded to it), in binary128.
using Seen = Quad (*)(double);
template <class Scalar>
Quad seen_by(double x) {
  return Quad(static_cast<Scalar>(x));
}

struct ClosedForm {
  std::vector<Term> qdd;
  std::vector<Term> nu, tau_cmd;  // the held arm only
  std::vector<Quad> beta;         // its setpoints E_cstr,N
};
// The answer of an unconstrained case.
ClosedForm accelerations(std::vector<Term> qdd) {
  ClosedForm f;
  f.qdd = std::move(qdd);
  return f;
}

struct Case {
  std::string name;
  std::string urdf;
  std::vector<State> states;
  // The model numbers the loader read (the spin case's rotated tensor) are in `chain`.
  std::function<ClosedForm(const model::Chain& chain, Seen seen, const Inputs& in)> closed_form;
  std::size_t constraints = 0;
  unsigned status = solver::status_ok;
  Eigen::Vector3d gravity{0, 0, -kGravity};
};
void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }  // for gtest's messages

// ---- URDF text -----------------------------------------------------------------------------

std::string text(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);  // round-trips
}
std::string text(const std::array<double, 3>& v) { return text(v[0]) + " " + text(v[1]) + " " + text(v[2]); }

// <inertial>: mass, centre of mass and rpy of the inertial frame, tensor about the com.
struct Inertial {
  double mass;
  std::array<double, 3> com, rpy;
  double ixx, iyy, izz, ixy, ixz, iyz;
};

std::string link(const std::string& name, const Inertial& in) {
  return "<link name=\"" + name + "\"><inertial><origin xyz=\"" + text(in.com) + "\" rpy=\"" + text(in.rpy) +
         "\"/><mass value=\"" + text(in.mass) + "\"/><inertia ixx=\"" + text(in.ixx) + "\" iyy=\"" + text(in.iyy) +
         "\" izz=\"" + text(in.izz) + "\" ixy=\"" + text(in.ixy) + "\" ixz=\"" + text(in.ixz) + "\" iyz=\"" +
         text(in.iyz) + "\"/></inertial></link>\n";
}

// A joint; a moving one gets `axis` and limits far from every state and torque here.
std::string joint(const std::string& name, const std::string& type, const std::string& parent,
                  const std::string& child, const std::array<double, 3>& xyz, const std::array<double, 3>& axis,
                  const std::array<double, 3>& rpy = {0, 0, 0}) {
  std::string xml = "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
                    "\"/><child link=\"" + child + "\"/><origin xyz=\"" + text(xyz) + "\" rpy=\"" + text(rpy) + "\"/>";
  if (type != "fixed")
    xml += "<axis xyz=\"" + text(axis) + "\"/><limit effort=\"1000\" velocity=\"100\" lower=\"-10\" upper=\"10\"/>";
  return xml + "</joint>\n";
}

std::string robot(const std::string& body) {
  return "<robot name=\"closed_form\"><link name=\"base\"/>\n" + body + "</robot>";
}

model::Chain load_urdf_text(const std::string& urdf) {
  test::TempDir dir;
  model::ChainSpec spec;
  spec.urdf = dir.write("robot.urdf", urdf);
  return model::load_chain(spec);
}

constexpr double kPi = 3.14159265358979323846;  // C++17: no std::numbers
constexpr std::array<double, 3> kY{0, 1, 0};

// 1. Pendulum about y, com at l below the joint: (I + m l²) q̈ = τ − m g l sin q.
Case pendulum() {
  const Inertial bob{1.5, {0, 0, -0.375}, {0, 0, 0}, 0.0625, 0.046875, 0.03125, 0.0078125, -0.00390625, 0.005859375};
  Case c{"pendulum", robot(joint("swing", "revolute", "base", "bob", {0, 0, 0}, kY) + link("bob", bob)),
         {{{0}, {0}, {0}},
          {{0}, {2}, {1.5}},
          {{kPi / 3}, {0}, {0}},
          {{kPi / 3}, {-3}, {2.5}},
          {{-2.5}, {1.25}, {-4}},
          {{kPi / 2}, {0.5}, {0}},
          {{3}, {-1}, {7}}},
         {}};
  c.closed_form = [bob](const model::Chain&, Seen seen, const Inputs& in) {
    const Term m = term(seen(bob.mass)), l = term(-seen(bob.com[2])), g = term(seen(kGravity));
    const Term inertia = term(seen(bob.iyy)) + m * l * l;
    return accelerations({(term(in.tau[0]) - m * g * l * angle(in.q[0]).sin) / inertia});
  };
  return c;
}

// 2. Double pendulum in the x-z plane (Lagrange): M(q) q̈ = τ − C(q, q̇) q̇ − G(q) with
//    M11 = I1 + I2 + m1 c1² + m2 (l1² + c2² + 2 l1 c2 cos q2),  M12 = I2 + m2 (c2² + l1 c2 cos q2),
//    M22 = I2 + m2 c2²,  h = m2 l1 c2 sin q2,  C q̇ = [−h (2 q̇1 q̇2 + q̇2²); h q̇1²],
//    G = [(m1 c1 + m2 l1) g sin q1 + m2 c2 g sin(q1 + q2); m2 c2 g sin(q1 + q2)].
Case double_pendulum() {
  const Inertial upper{1.25, {0, 0, -0.25}, {0, 0, 0}, 0.03125, 0.0234375, 0.015625, 0.001953125, 0, -0.0009765625};
  const Inertial lower{0.75, {0, 0, -0.3125}, {0, 0, 0}, 0.015625, 0.01171875, 0.0078125, 0, 0.0009765625, 0};
  const double l1 = 0.5;
  Case c{"double_pendulum",
         robot(joint("shoulder", "revolute", "base", "upper", {0, 0, 0}, kY) + link("upper", upper) +
               joint("elbow", "revolute", "upper", "lower", {0, 0, -l1}, kY) + link("lower", lower)),
         {{{0, 0}, {0, 0}, {0, 0}},
          {{0, 0}, {1.5, -2}, {3, -1}},
          {{kPi / 3, -kPi / 3}, {0, 0}, {0, 0}},
          {{kPi / 3, kPi / 2}, {-2.5, 1}, {-1.5, 0.5}},
          {{-2, 0.75}, {3, 4}, {2, 2}},
          {{2.5, -1.25}, {-1, -3.5}, {0, -4}}},
         {}};
  c.closed_form = [upper, lower, l1](const model::Chain&, Seen seen, const Inputs& in) {
    const Term m1 = term(seen(upper.mass)), c1 = term(-seen(upper.com[2])), I1 = term(seen(upper.iyy));
    const Term m2 = term(seen(lower.mass)), c2 = term(-seen(lower.com[2])), I2 = term(seen(lower.iyy));
    const Term l = term(seen(l1)), g = term(seen(kGravity)), two = term(2);
    const Angle q1 = angle(in.q[0]), q2 = angle(in.q[1]), q12 = q1 + q2;
    const Term qd1 = term(in.qd[0]), qd2 = term(in.qd[1]);
    const Term M11 = I1 + I2 + m1 * c1 * c1 + m2 * (l * l + c2 * c2 + two * l * c2 * q2.cos);
    const Term M12 = I2 + m2 * (c2 * c2 + l * c2 * q2.cos);
    const Term M22 = I2 + m2 * c2 * c2;
    const Term h = m2 * l * c2 * q2.sin;
    const TermVector<2> coriolis{Term{} - h * (two * qd1 * qd2 + qd2 * qd2), h * qd1 * qd1};
    const TermVector<2> gravity{(m1 * c1 + m2 * l) * g * q1.sin + m2 * c2 * g * q12.sin, m2 * c2 * g * q12.sin};
    const TermVector<2> rhs{term(in.tau[0]) - coriolis[0] - gravity[0], term(in.tau[1]) - coriolis[1] - gravity[1]};
    const TermVector<2> qdd = solve<2>({{{M11, M12}, {M12, M22}}}, rhs);
    return accelerations({qdd[0], qdd[1]});
  };
  return c;
}

// 3. Cart-pole: a cart of mass mc sliding along x, a pole (m, com l above its joint, I about the
//    com) hinged on it about y: M = [mc + m, m l cos q2; m l cos q2, I + m l²],
//    C q̇ = [−m l sin q2 q̇2²; 0], G = [0; −m g l sin q2].
Case cart_pole() {
  const Inertial cart{2.5, {0, 0, 0}, {0, 0, 0}, 0.125, 0.1875, 0.25, 0, 0, 0};
  const Inertial pole{0.5, {0, 0, 0.4375}, {0, 0, 0}, 0.0078125, 0.0078125, 0.0009765625, 0.00048828125, 0, 0};
  Case c{"cart_pole",
         robot(joint("rail", "prismatic", "base", "cart", {0, 0, 0}, {1, 0, 0}) + link("cart", cart) +
               joint("hinge", "revolute", "cart", "pole", {0, 0, 0}, kY) + link("pole", pole)),
         {{{0, 0}, {0, 0}, {0, 0}},
          {{0, 0}, {1, 2}, {5, 0}},
          {{0.5, kPi / 3}, {0, 0}, {0, 0}},
          {{-1.25, -kPi / 3}, {-2, 3}, {-3, 0.25}},
          {{2, 3}, {0.5, -4}, {10, -1}},
          {{0, kPi / 2}, {0, 1.5}, {0, 0}}},
         {}};
  c.closed_form = [cart, pole](const model::Chain&, Seen seen, const Inputs& in) {
    const Term mc = term(seen(cart.mass)), m = term(seen(pole.mass)), l = term(seen(pole.com[2]));
    const Term I = term(seen(pole.iyy)), g = term(seen(kGravity));
    const Angle q2 = angle(in.q[1]);
    const Term qd2 = term(in.qd[1]);
    const Term coupling = m * l * q2.cos;
    const TermVector<2> rhs{term(in.tau[0]) + m * l * q2.sin * qd2 * qd2, term(in.tau[1]) + m * g * l * q2.sin};
    const TermVector<2> qdd = solve<2>({{{mc + m, coupling}, {coupling, I + m * l * l}}}, rhs);
    return accelerations({qdd[0], qdd[1]});
  };
  return c;
}

// 4. Free fall along a prismatic joint whose frame is turned upside down (roll π, folded
//    exactly): its axis +z points along gravity, so with τ = 0, q̈ = +g whatever q, q̇ and the
//    com: m q̈ = τ + m g.
Case free_fall() {
  const Inertial block{1.5, {0.125, -0.0625, 0.25}, {0, 0, 0}, 0.0625, 0.046875, 0.03125, 0, 0, 0};
  Case c{"free_fall",
         robot(joint("drop", "prismatic", "base", "block", {0, 0, 1}, {0, 0, 1}, {kPi, 0, 0}) + link("block", block)),
         {{{0}, {0}, {0}}, {{0.75}, {3}, {0}}, {{-2}, {-1.5}, {0}}, {{5}, {0}, {0}}},
         {}};
  c.closed_form = [block](const model::Chain&, Seen seen, const Inputs& in) {
    const Term m = term(seen(block.mass));
    return accelerations({(term(in.tau[0]) + m * term(seen(kGravity))) / m});
  };
  return c;
}

// 5. A three-joint planar arm (joints about y, non-collinear offsets) at rest, its tip held by
//    six unit directions α_k = e_k in the tip frame. Out of the plane the tip cannot move:
//    those three rows of E^A_cstr,0 are exactly zero and their pivots are dropped (C2), ν = 0
//    there. In the plane J is invertible: standing still, q̈ = 0; the physical wrench on the tip
//    is +α ν (docs/derivation.md, "The traps"), so ν is the static wrench W (moment about the
//    tip, force, tip frame) with Jᵀ W = G(q) − τff (statics: joint torques and the wrench hold
//    the weight), and τcmd = τff + Jᵀ W (T1) = G(q). Standing still is not β = 0: Ẍ is spatial
//    acceleration minus gravity (O4), so the setpoints are β = [0; R_tipᵀ (−g)] ("The traps").
const std::array<Inertial, 3> kArmLinks{
    Inertial{1.5, {0.125, 0, -0.25}, {0, 0, 0}, 0.03125, 0.03125, 0.0078125, 0.001953125, 0, 0},
    Inertial{1, {0.25, 0, -0.125}, {0, 0, 0}, 0.015625, 0.0234375, 0.015625, 0, 0.001953125, 0},
    Inertial{0.5, {0.125, 0, -0.0625}, {0, 0, 0}, 0.0078125, 0.0078125, 0.00390625, 0, 0, 0.0009765625}};
// Joint 2 in link 1, joint 3 in link 2, the tip in link 3.
const std::array<std::array<double, 3>, 3> kArmOffsets{{{0.25, 0, -0.5}, {0.5, 0, -0.25}, {0.25, 0, -0.125}}};

// The arm at q, in the base's x-z plane.
struct ArmPose {
  std::array<Angle, 3> orientation;  // of link k
  std::array<Planar, 4> joint;       // p_1..p_3, then the tip
  std::array<Planar, 3> com;         // c_k
};

ArmPose arm_pose(Seen seen, const std::vector<Quad>& q) {
  const auto planar = [seen](const std::array<double, 3>& v) { return Planar{term(seen(v[0])), term(seen(v[2]))}; };
  ArmPose pose;
  for (std::size_t k = 0; k < 3; ++k) {
    pose.orientation[k] = k == 0 ? angle(q[0]) : pose.orientation[k - 1] + angle(q[k]);
    pose.joint[k + 1] = pose.joint[k] + rotated(pose.orientation[k], planar(kArmOffsets[k]));
    pose.com[k] = pose.joint[k] + rotated(pose.orientation[k], planar(kArmLinks[k].com));
  }
  return pose;
}

// Jᵀ: row j is the tip twist (ω_y, v_x, v_z) per q̇_j, e_y × r = (1, r_z, −r_x), r = p_tip − p_j.
TermMatrix<3> tip_jacobian_transposed(const ArmPose& pose) {
  TermMatrix<3> Jt;
  for (std::size_t j = 0; j < 3; ++j) {
    const Planar r = pose.joint[3] - pose.joint[j];
    Jt[j] = {term(1), r.z, Term{} - r.x};
  }
  return Jt;
}

// G_j = ∂V/∂q_j = −Σ_{k≥j} m_k g (c_k − p_j)_x (the moment of the weights about joint j).
TermVector<3> gravity_torque(const ArmPose& pose, Seen seen) {
  TermVector<3> G;
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t k = j; k < 3; ++k)
      G[j] = G[j] - term(seen(kArmLinks[k].mass)) * term(seen(kGravity)) * (pose.com[k] - pose.joint[j]).x;
  return G;
}

// M_ij = Σ_{k ≥ i, j} m_k v_k,i · v_k,j + I_k, with v_k,j = e_y × (c_k − p_j) the velocity of
// com k per q̇_j and I_k the tensor's yy entry about the com.
TermMatrix<3> joint_space_inertia(const ArmPose& pose, Seen seen) {
  TermMatrix<3> M;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i <= k; ++i)
      for (std::size_t j = 0; j <= k; ++j) {
        const Planar ri = pose.com[k] - pose.joint[i], rj = pose.com[k] - pose.joint[j];
        M[i][j] = M[i][j] + term(seen(kArmLinks[k].mass)) * (ri.z * rj.z + ri.x * rj.x) + term(seen(kArmLinks[k].iyy));
      }
  return M;
}

ClosedForm held_arm_closed_form(Seen seen, const Inputs& in) {
  const ArmPose pose = arm_pose(seen, in.q);
  const TermMatrix<3> Jt = tip_jacobian_transposed(pose);
  const TermVector<3> G = gravity_torque(pose, seen);
  TermVector<3> held, wrench_value;  // G − τff; W at its value
  for (std::size_t j = 0; j < 3; ++j) held[j] = G[j] - term(in.tau[j]);
  const TermVector<3> W = solve<3>(Jt, held);  // (n_y, F_x, F_z), base frame, about the tip
  for (std::size_t j = 0; j < 3; ++j) wrench_value[j] = term(W[j].value);
  const TermVector<3> JtW = times(Jt, W), balance = times(Jt, wrench_value);
  // q̈ = M⁻¹ (τff + Jᵀ W − G) = 0 from generalized forces that cancel: its size is theirs through
  // M⁻¹ (W at its value: the error of W is ν's, checked on its own).
  TermVector<3> unbalanced;
  for (std::size_t j = 0; j < 3; ++j) unbalanced[j] = {0, (term(in.tau[j]) + balance[j] - G[j]).size};
  const TermVector<3> qdd = solve<3>(joint_space_inertia(pose, seen), unbalanced);
  const Angle& tip = pose.orientation[2];  // R_tip = R_y(θ): W in the tip frame is R_tipᵀ W
  ClosedForm f;
  f.qdd.assign(qdd.begin(), qdd.end());
  f.nu = {Term{}, W[0], Term{}, tip.cos * W[1] - tip.sin * W[2], Term{}, tip.sin * W[1] + tip.cos * W[2]};
  for (std::size_t j = 0; j < 3; ++j) f.tau_cmd.push_back(term(in.tau[j]) + JtW[j]);
  const Term g = term(seen(kGravity));
  f.beta = {0, 0, 0, -(g * tip.sin).value, 0, (g * tip.cos).value};
  return f;
}

Case held_arm() {
  Case c{"held_arm",
         robot(joint("j1", "revolute", "base", "l1", {0, 0, 0}, kY) + link("l1", kArmLinks[0]) +
               joint("j2", "revolute", "l1", "l2", kArmOffsets[0], kY) + link("l2", kArmLinks[1]) +
               joint("j3", "revolute", "l2", "l3", kArmOffsets[1], kY) + link("l3", kArmLinks[2]) +
               joint("flange", "fixed", "l3", "tip", kArmOffsets[2], {}) + "<link name=\"tip\"/>\n"),
         {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
          {{0, 0, 0}, {0, 0, 0}, {2, -1, 0.5}},
          {{kPi / 3, -kPi / 3, kPi / 6}, {0, 0, 0}, {0, 0, 0}},
          {{-1, 2, -0.5}, {0, 0, 0}, {-3, 1.5, 4}},
          {{2.5, 1, 1.5}, {0, 0, 0}, {0.25, 0, -2}}},
         [](const model::Chain&, Seen seen, const Inputs& in) { return held_arm_closed_form(seen, in); },
         6,
         solver::status_constraint_rank_deficient};
  return c;
}

// 6. A body spun about its principal axis of largest moment izz (com on it, at the link origin),
//    turned by a non-trivial rpy so that the axis a = R_rpy e_z is no coordinate axis of the
//    link; no gravity: q̈ = (τ − a · (ω × Ā ω)) / (aᵀ Ā a) with ω = a q̇, and the gyroscopic term
//    a · (ω × Ā ω) vanishes (ω ∥ a; its size is what rounding may leave of it). a and Ā are the
//    loader's (rounded in double: rpy through a quaternion, R I Rᵀ), so that binary128 checks the
//    solver's equations, not the loader; ClosedFormSpin below checks that aᵀ Ā a is izz, that Ā
//    has no product of inertia about a (Ā a = izz a) and that the solver's gyroscopic wrench
//    vanishes.
const Inertial kSpinner{2, {0, 0, 0}, {0.3, 0.7, 1.1}, 0.25, 0.375, 0.5, 0, 0, 0};

// R_rpy e_z, R_rpy = R_z(yaw) R_y(pitch) R_x(roll) (URDF).
std::array<double, 3> spin_axis() {
  const double cr = std::cos(kSpinner.rpy[0]), sr = std::sin(kSpinner.rpy[0]);
  const double cp = std::cos(kSpinner.rpy[1]), sp = std::sin(kSpinner.rpy[1]);
  const double cy = std::cos(kSpinner.rpy[2]), sy = std::sin(kSpinner.rpy[2]);
  return {cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr};
}

Case principal_spin() {
  Case c{"principal_spin",
         robot(joint("spin", "continuous", "base", "rotor", {0.5, 0.25, 1}, spin_axis()) + link("rotor", kSpinner)),
         {{{0}, {0}, {0}}, {{0}, {5}, {0.75}}, {{kPi / 3}, {-12}, {0}}, {{-2}, {12}, {-3}}, {{kPi / 3}, {0}, {2}}},
         {}};
  c.gravity.setZero();
  c.closed_form = [](const model::Chain& chain, Seen seen, const Inputs& in) {
    TermVector<3> a, omega;
    TermMatrix<3> inertia;
    for (std::size_t r = 0; r < 3; ++r) {
      a[r] = term(seen(chain.joints[1].axis[r]));
      omega[r] = a[r] * term(in.qd[0]);
      for (std::size_t k = 0; k < 3; ++k) inertia[r][k] = term(seen(chain.bodies[1].inertia.A(r, k)));
    }
    const Term gyroscopic{0, dot(a, cross(omega, times(inertia, omega))).size};
    return accelerations({(term(in.tau[0]) - gyroscopic) / dot(a, times(inertia, a))});
  };
  return c;
}

// ---- Running the solvers -------------------------------------------------------------------

// One torque driver and a zero wrench on the tip (so that Alg. 4 has a pure external-force
// track to leave out of the constraint's reaction), Nc tip directions.
solver::DriverLayout layout_for(const model::Chain& chain, std::size_t nc, bool composed) {
  solver::DriverLayout layout;
  layout.torques = {"tau"};
  layout.external_forces = {{"push", chain.tip_link}};
  layout.constraints = nc;
  composed ? layout.compose_all() : layout.decompose_all();
  return layout;
}

// The state in double with α_k = e_k; β is set per scalar from the closed form.
solver::SolveInputs<double> posed(const State& s, std::size_t nc) {
  const auto vector = [](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  };
  solver::SolveInputs<double> in{vector(s.q), vector(s.qd), {vector(s.tau)}, {spatial::Force<double>{}}, {},
                                 solver::ConstraintVector<double>::Zero(nc)};
  for (std::size_t k = 0; k < nc; ++k) {
    spatial::Force<double> direction;
    (k < 3 ? direction.moment : direction.force)[k % 3] = 1;
    in.alpha.push_back(direction);
  }
  return in;
}

template <class Vector>
std::vector<Quad> in_quad(const Vector& v) {
  std::vector<Quad> out;
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(Quad(v[i]));
  return out;
}

// Largest |computed − value| / (eps size), each within kUlps (0 size: exactly the value).
template <class Vector>
double largest_ulps(const Vector& computed, const std::vector<Term>& expected, double eps, const std::string& what) {
  double largest = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Term& e = expected[i];
    EXPECT_LE(e.size, Quad(kLargestSize)) << what << "[" << i << "]: the tolerance's ceiling";
    const Quad error = abs(Quad(computed[static_cast<Eigen::Index>(i)]) - e.value);
    const double ulps = error == Quad(0) ? 0.0 : static_cast<double>(error / (Quad(eps) * e.size));
    EXPECT_LE(ulps, kUlps) << what << "[" << i << "] = " << computed[static_cast<Eigen::Index>(i)] << ", closed form "
                           << e.value << " (size " << e.size << ")";
    largest = std::max(largest, ulps);
  }
  return largest;
}

// The largest error of ReferenceSolver<Scalar> over the case's states, policies and layouts.
template <class Scalar>
double largest_error(const Case& c, const model::Chain& chain, const char* scalar) {
  const double eps = static_cast<double>(std::numeric_limits<Scalar>::epsilon());
  solver::SolverOptions options;
  options.gravity = c.gravity;
  double largest = 0;
  for (bool composed : {true, false}) {
    solver::ReferenceSolver<Scalar> s(chain, layout_for(chain, c.constraints, composed), options);
    for (std::size_t n = 0; n < c.states.size(); ++n) {
      solver::SolveInputs<Scalar> in = posed(c.states[n], c.constraints).template cast<Scalar>();
      const ClosedForm expected =
          c.closed_form(chain, &seen_by<Scalar>, {in_quad(in.q), in_quad(in.qd), in_quad(in.torques[0])});
      for (std::size_t k = 0; k < expected.beta.size(); ++k) in.beta[k] = static_cast<Scalar>(expected.beta[k]);
      s.prepare(in);
      for (Policy policy : kPolicies) {
        const std::string where = c.name + " " + scalar + " " + (composed ? "Alg. 1 " : "Alg. 2 ") +
                                  solver::name(policy) + " state " + std::to_string(n) + " ";
        const solver::Solution<Scalar>& sol = s.solve(policy, in.beta);
        EXPECT_EQ(s.status(), c.status) << where;
        largest = std::max(largest, largest_ulps(sol.qdd, expected.qdd, eps, where + "qdd"));
        largest = std::max(largest, largest_ulps(sol.nu, expected.nu, eps, where + "nu"));
        largest = std::max(largest, largest_ulps(sol.tau_cmd, expected.tau_cmd, eps, where + "tau_cmd"));
      }
    }
  }
  return largest;
}

class ClosedFormCase : public ::testing::TestWithParam<Case> {};

TEST_P(ClosedFormCase, ReferenceSolverGivesTheTextbookAnswer) {
  const Case& c = GetParam();
  const model::Chain chain = load_urdf_text(c.urdf);
  const double quad = largest_error<Quad>(c, chain, "binary128");
  const double dbl = largest_error<double>(c, chain, "double");
  const double flt = largest_error<float>(c, chain, "float");
  std::printf("[closed form] %s: largest error in eps of the terms' size: binary128 %.2f, double %.2f, float %.2f "
              "(bound %g)\n",
              c.name.c_str(), quad, dbl, flt, kUlps);
}

INSTANTIATE_TEST_SUITE_P(Textbook, ClosedFormCase,
                         ::testing::Values(pendulum(), double_pendulum(), cart_pole(), free_fall(), held_arm(),
                                           principal_spin()),
                         [](const auto& info) { return info.param.name; });

// The spin case's premise, from the URDF numbers: the loader rotated the tensor (F3) so that
// the joint axis a = R_rpy e_z is a principal axis with moment izz (Ā a = izz a), and the
// solver's gyroscopic wrench Fb = ω × Ā ω (O3) vanishes for ω = a q̇. The loader's R comes from
// rpy through a quaternion and back, and R I Rᵀ is rounded: a few eps of |I| per entry.
// Measured: 0.50 eps · izz for Ā a − izz a, 0.22 eps · izz q̇² for Fb; allowed kUlps (a margin of 8).
TEST(ClosedFormSpin, AxisIsAPrincipalAxisOfTheLoadedInertia) {
  const model::Chain chain = load_urdf_text(principal_spin().urdf);
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const model::Vec3 a = chain.joints[1].axis;
  const model::Mat3& inertia = chain.bodies[1].inertia.A;
  const double izz = kSpinner.izz;
  const double principal_error = (inertia * a - izz * a).cwiseAbs().maxCoeff() / (eps * izz);
  EXPECT_LE(principal_error, kUlps) << "A a = " << (inertia * a).transpose() << ", izz a = " << (izz * a).transpose();
  EXPECT_LE((a - Eigen::Map<const model::Vec3>(spin_axis().data())).cwiseAbs().maxCoeff(), kUlps * eps);

  const double qd = 12;
  solver::ReferenceSolver<double> s(chain, layout_for(chain, 0, true), {});
  s.outward(Eigen::VectorXd::Constant(1, 0.5), Eigen::VectorXd::Constant(1, qd));
  const spatial::Force<double>& bias = s.kinematics().body[1].bias_force;
  const double gyroscopic_error = bias.moment.cwiseAbs().maxCoeff() / (eps * izz * qd * qd);
  EXPECT_LE(gyroscopic_error, kUlps) << "Fb moment " << bias.moment.transpose();
  EXPECT_EQ(bias.force, model::Vec3::Zero());  // com on the axis: no centripetal force
  std::printf("[closed form] principal_spin loader: |A a - izz a| %.2f eps izz, |Fb| %.2f eps izz qd^2 (bound %g)\n",
              principal_error, gyroscopic_error, kUlps);
}

// A free rigid body (a floating base and nothing else, F5): Euler's equations and Newton's in its
// own frame, I ω̇ + ω × I ω = 0 and m (v̇ + ω × v) = m Rᵀ g, with I = diag(1, 2, 3) kg m², m = 2 kg,
// the centre of mass at the origin, ω = (1, 2, 3) rad/s, v = (0.5, 0, 0) m/s and the base turned a
// quarter turn about x (Rᵀ g = (0, −9.81, 0)): ω̇ = (−6, 3, −2/3), v̇ = (0, −11.31, 1); with a
// wrench τ_1..6 = [n; f] on it, ω̇ += I⁻¹ n and v̇ += f / m. The q of the six coordinates is never
// read (NaN here). Each value within kUlps eps of the largest term.
TEST(ClosedFormFloatingBase, FreeBodyFollowsEulerAndNewton) {
  model::Chain chain;
  chain.source = "free body";
  chain.root_link = chain.tip_link = "body";
  chain.bodies.push_back(model::Body{"body", {}, model::Inertia{}, 0});
  chain.joints.push_back(model::Joint{});
  chain.parent.push_back(0);
  model::add_floating_base(chain, model::Inertia::rigid(2.0, model::Vec3::Zero(), model::Vec3(1, 2, 3).asDiagonal()), 2.0);
  ASSERT_EQ(chain.dof(), 6u);
  model::Mat3 R;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;  // world_R_base: a quarter turn about x
  solver::ReferenceSolver<double> s(chain, layout_for(chain, 0, true), {});
  Eigen::VectorXd qd(6);
  qd << 1, 2, 3, 0.5, 0, 0;
  s.outward(Eigen::VectorXd::Constant(6, std::numeric_limits<double>::quiet_NaN()), qd, R);
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(6);
  Eigen::VectorXd expected(6);
  expected << -6, 3, -2.0 / 3, 0, -11.31, 1;  // ω̇ = −I⁻¹ (ω × I ω), v̇ = Rᵀ g − ω × v
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      tau << 0.5, -1, 3, 4, -2, 1;  // [n; f]
      expected.head(3) += model::Vec3(0.5 / 1, -1.0 / 2, 3.0 / 3);
      expected.tail(3) += model::Vec3(4, -2, 1) / 2.0;
    }
    s.drivers().torques[0] = tau;
    s.decompose();
    const Eigen::VectorXd qdd = s.solve(Policy::original, {}).qdd;
    const double error = (qdd - expected).cwiseAbs().maxCoeff() / (std::numeric_limits<double>::epsilon() * 11.31);
    EXPECT_LE(error, kUlps) << "pass " << pass << ": qdd " << qdd.transpose() << ", closed form " << expected.transpose();
    EXPECT_EQ(s.status(), solver::status_ok);
    std::printf("[closed form] free body, %s: %.2f eps of the largest term (bound %g)\n",
                pass == 0 ? "no wrench" : "with a wrench", error, kUlps);
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
