#include "report/kdl_row.hpp"

#ifndef SWEEPGEN_HAVE_KDL

namespace sweepgen::report {

VariantResult measure_kdl(const scene::Scene&, const model::Chain&, const std::vector<Problem>&, const TimingOptions&) {
  return {"kdl", "double", "KDL not found at build time", {}, {}};
}

}  // namespace sweepgen::report

#else

#include <cstdlib>
#include <kdl/chain.hpp>
#include <kdl/chainhdsolver_vereshchagin.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>

#include "oracle/kdl_chain.hpp"
#include "oracle/kdl_convention.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::report {
namespace {

using oracle::body_rotations;
using oracle::from_kdl_base;
using oracle::kdl_chain;
using oracle::kdl_directions;
using oracle::kdl_joints;
using oracle::kdl_root_acceleration;
using oracle::to_kdl_base;

VariantResult unavailable(const std::string& why) { return {"kdl", "double", why, {}, {}}; }

// One state in KDL's terms.
struct KdlInput {
  KDL::JntArray q, qd, ff, beta;
  KDL::Jacobian alfa;
  KDL::Wrenches f_ext;
  Eigen::Matrix3d R_tip_body;  // rotation of body N into the base
};

}  // namespace

VariantResult measure_kdl(const scene::Scene& s, const model::Chain& chain, const std::vector<Problem>& problems,
                          const TimingOptions& timing) {
  if (chain.floating_base) return unavailable("KDL's Vereshchagin solver takes a fixed base");
  if (!chain.is_chain()) return unavailable("KDL's Vereshchagin solver takes a chain, not a tree");
  if (s.layout.listed_sets() > 0)
    return unavailable("KDL's Vereshchagin solver takes one constraint set, on the chain's tip");
  if (!chain.couplings.empty())
    return unavailable("KDL takes a <mimic> joint as a joint of its own; the scene couples them (mimic: coupled)");
  KDL::Chain kdl;
  std::string why;
  if (!kdl_chain(s.chain.urdf, chain, kdl, why)) return unavailable(why);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const unsigned segments = kdl.getNrOfSegments();

  // Inputs in base orientation, from the rotations of the outward sweep (untimed).
  solver::ReferenceSolver<double> kinematics(chain, s.layout, s.solver_options());
  const model::Frame& tip = chain.tip();
  std::vector<KdlInput> inputs;
  inputs.reserve(problems.size());
  for (const Problem& p : problems) {
    kinematics.outward(p.q, p.qd);
    const std::vector<Eigen::Matrix3d> R = body_rotations(kinematics.kinematics());
    KdlInput in;
    in.q = kdl_joints(p.q);
    in.qd = kdl_joints(p.qd);
    in.ff = kdl_joints(p.tau_ff);
    in.beta = KDL::JntArray(static_cast<unsigned>(nc));
    in.beta.data = p.beta;
    std::vector<spatial::Force<double>> on_body_n;  // body N frame, about its origin
    for (std::size_t k = 0; k < nc; ++k) on_body_n.push_back(tip.X.apply_transpose(p.alpha[k]));
    in.alfa = kdl_directions(on_body_n, R[n]);
    in.f_ext.assign(segments, KDL::Wrench::Zero());
    for (std::size_t e = 0; e < p.wrenches.size(); ++e) {
      const model::Frame& frame = chain.frames.at(s.layout.external_forces[e].link);
      const spatial::Force<double> on_body = frame.X.apply_transpose(p.wrenches[e]);
      in.f_ext[frame.body - 1] += to_kdl_base(on_body, R[frame.body]);
    }
    in.R_tip_body = R[n];
    inputs.push_back(std::move(in));
  }

  const Eigen::Vector3d g = s.gravity;
  KDL::ChainHdSolver_Vereshchagin hd(kdl, kdl_root_acceleration(g), static_cast<unsigned>(nc));
  std::vector<KDL::JntArray> qdd(problems.size(), KDL::JntArray(static_cast<unsigned>(n)));
  std::vector<Eigen::VectorXd> nu(problems.size(), Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nc)));
  std::vector<KDL::Twist> tip_acceleration(problems.size());
  KDL::JntArray constraint_torques(static_cast<unsigned>(n));
  std::vector<KDL::Twist> accelerations(segments + 1);
  int failure = 0;
  const auto call = [&](std::size_t state) {
    const KdlInput& in = inputs[state];
    const int status = hd.CartToJnt(in.q, in.qd, qdd[state], in.alfa, in.beta, in.f_ext, in.ff, constraint_torques);
    if (status != 0) failure = status;
    hd.getContraintForceMagnitude(nu[state]);
    hd.getTransformedLinkAcceleration(accelerations);
    tip_acceleration[state] = accelerations[segments];
  };
  VariantResult result{"kdl", "double", "", time_calls(problems.size(), timing, call), {}};
  if (failure != 0) return unavailable("KDL CartToJnt failed (status " + std::to_string(failure) + ")");

  KDL::ChainJntToJacSolver jacobian_solver(kdl);
  KDL::Jacobian J(static_cast<unsigned>(n));
  for (std::size_t state = 0; state < problems.size(); ++state) {
    const KdlInput& in = inputs[state];
    Outcome o;
    for (std::size_t i = 0; i < n; ++i) o.qdd.push_back(qdd[state](static_cast<unsigned>(i)));
    // τcmd = τff + J^T w, w = −alfa ν_KDL the physical constraint wrench on the last moving
    // link (about its origin, base orientation; J's rows [linear; angular] pair with it).
    if (jacobian_solver.JntToJac(in.q, J) < 0) return unavailable("KDL JntToJac failed");
    const Eigen::VectorXd tau = problems[state].tau_ff + J.data.transpose() * (-(in.alfa.data * nu[state]));
    for (std::size_t i = 0; i < n; ++i) o.tau_cmd.push_back(tau[static_cast<Eigen::Index>(i)]);
    for (std::size_t k = 0; k < nc; ++k) o.nu.push_back(-nu[state][static_cast<Eigen::Index>(k)]);  // KDL's ν is −ν
    // KDL's Ẍ_N (base orientation, about body N's origin) -> body N frame -> tip frame.
    const spatial::Motion<double> body = from_kdl_base(tip_acceleration[state], in.R_tip_body);
    const spatial::Motion<double> at_tip = tip.X.apply(body);
    for (int k = 0; k < 3; ++k) {
      o.tip_acceleration[static_cast<std::size_t>(k)] = at_tip.angular[k];
      o.tip_acceleration[static_cast<std::size_t>(3 + k)] = at_tip.linear[k];
    }
    o.link_acceleration.assign(nc, o.tip_acceleration);  // every direction is on the tip
    result.outcomes.push_back(std::move(o));
  }
  return result;
}

}  // namespace sweepgen::report

#endif
