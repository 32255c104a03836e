// KDL 1.5.1's ChainHdSolver_Vereshchagin on the Panda, chain panda_link0 -> panda_link7 (KDL's
// solver crashes on chains with fixed joints, so not up to panda_hand as the scenes), on the
// random problems of robots/panda/panda_nc6.yaml (bench/support/inputs.hpp): the same q, qd,
// tau_ff; the `contact` wrench on panda_link5 and the `push` wrench on panda_link7 (the last
// moving link, standing in for panda_hand); the first Nc of the random unit directions alpha
// and setpoints beta. The wrenches and directions are passed to KDL as numbers without the
// frame translation of tests/test_reference_kdl.cpp (KDL wants them in base orientation): the
// cost of the solver does not depend on which frame the random numbers were meant in, and
// external forces are always processed by KDL (a zero wrench costs the same).
#pragma once

#include <kdl/chain.hpp>
#include <kdl/chainhdsolver_vereshchagin.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/inputs.hpp"

namespace sweepgen::bench {

class KdlBench {
 public:
  explicit KdlBench(unsigned nc) : nc_(nc) {
    const std::string source = SWEEPGEN_SOURCE_DIR;
    KDL::Tree tree;
    if (!kdl_parser::treeFromFile(source + "/robots/panda/panda.urdf", tree))
      throw std::runtime_error("kdl_parser cannot read robots/panda/panda.urdf");
    if (!tree.getChain("panda_link0", "panda_link7", chain_))
      throw std::runtime_error("KDL has no chain panda_link0 -> panda_link7");
    const unsigned n = chain_.getNrOfJoints();
    // Root acceleration: minus gravity (tests/test_reference_kdl.cpp).
    solver_ = std::make_unique<KDL::ChainHdSolver_Vereshchagin>(chain_, KDL::Twist(KDL::Vector(0, 0, 9.81), KDL::Vector::Zero()), nc);
    const SceneInputs s = make_inputs(source + "/robots/panda/panda_nc6.yaml");
    if (s.dof != n || s.constraints != 6) throw std::logic_error("panda_nc6 scene does not match the KDL chain");
    for (const auto& in : s.flat) {
      Problem p{KDL::JntArray(n), KDL::JntArray(n), KDL::JntArray(n), KDL::JntArray(nc), KDL::Jacobian(nc),
                KDL::Wrenches(chain_.getNrOfSegments(), KDL::Wrench::Zero())};
      const double* at = in.data();
      for (unsigned i = 0; i < n; ++i) p.q(i) = *at++;
      for (unsigned i = 0; i < n; ++i) p.qd(i) = *at++;
      for (unsigned i = 0; i < n; ++i) p.tau(i) = *at++;
      const auto wrench = [&at] {  // [moment; force] -> Wrench(force, torque)
        const KDL::Vector moment(at[0], at[1], at[2]), force(at[3], at[4], at[5]);
        at += 6;
        return KDL::Wrench(force, moment);
      };
      p.f_ext[4] = wrench();      // contact on panda_link5 (segment 4)
      p.f_ext[n - 1] = wrench();  // push, on panda_link7 here
      for (unsigned k = 0; k < 6; ++k, at += 6)
        if (k < nc)
          for (int r = 0; r < 3; ++r) {
            p.alfa(r, k) = at[3 + r];  // KDL rows: force, then moment
            p.alfa(3 + r, k) = at[r];
          }
      for (unsigned k = 0; k < 6; ++k, ++at)
        if (k < nc) p.beta(k) = *at;
      problems_.push_back(std::move(p));
    }
    qdd_ = KDL::JntArray(n);
    torques_ = KDL::JntArray(n);
  }
  std::size_t count() const { return problems_.size(); }
  unsigned constraints() const { return nc_; }

  // One CartToJnt call on problem i; returns qdd(0) (throws on a KDL error).
  double call(std::size_t i) {
    Problem& p = problems_[i];
    const int status = solver_->CartToJnt(p.q, p.qd, qdd_, p.alfa, p.beta, p.f_ext, p.tau, torques_);
    if (status != 0) throw std::runtime_error("KDL CartToJnt failed: " + std::to_string(status));
    return qdd_(0);
  }

 private:
  struct Problem {
    KDL::JntArray q, qd, tau, beta;
    KDL::Jacobian alfa;
    KDL::Wrenches f_ext;
  };
  unsigned nc_;
  KDL::Chain chain_;
  std::unique_ptr<KDL::ChainHdSolver_Vereshchagin> solver_;
  std::vector<Problem> problems_;
  KDL::JntArray qdd_, torques_;
};

}  // namespace sweepgen::bench
