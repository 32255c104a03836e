// The dense oracle's constraint rows of a scene's drivers (docs/derivation.md, section 9, (L2), (M1)),
// shared by the tests that hold the solver to Gauss' principle: each set's α_kᵀ J_A (a world set)
// or α_kᵀ J_rel (a set between two links), right-hand side β_k − α_kᵀ c, then each coupled
// <mimic> joint's e_mᵀ − k e_sᵀ, right-hand side 0; in the oracle's scalar.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "model/chain.hpp"
#include "oracle/dense_dynamics.hpp"
#include "solver/drivers.hpp"

namespace sweepgen::test {

// The oracle's frame for a set's frame A (or B): the transform link -> frame as R (frame -> link
// coordinates) and p (its origin in the link's).
template <class O>
typename O::AttachedFrame attached(const std::string& link, const model::Transform& X) {
  using S = typename O::Vec::Scalar;
  return {link, X.E.transpose().cast<S>(), X.r.cast<S>()};
}

template <class O>
struct DenseRows {
  typename O::Mat Jc;
  typename O::Vec rhs;
};

// `alpha`: the set directions' columns (6 × Nc); `beta`: their setpoints.
template <class O>
DenseRows<O> dense_rows(const O& o, const solver::DriverLayout& layout, const model::Chain& chain, const typename O::Vec& q,
                        const typename O::Vec& qd, const typename O::Mat& alpha, const typename O::Vec& beta) {
  using S = typename O::Vec::Scalar;
  const auto n = static_cast<Eigen::Index>(chain.dof()), nc = alpha.cols();
  const auto couplings = static_cast<Eigen::Index>(chain.couplings.size());
  DenseRows<O> rows{O::Mat::Zero(nc + couplings, n), O::Vec::Zero(nc + couplings)};
  Eigen::Index k = 0;
  for (const solver::ConstraintSet& set : layout.constraint_sets()) {
    const typename O::Mat a = alpha.middleCols(k, static_cast<Eigen::Index>(set.count));
    typename O::Jacobian J;
    typename O::Six c;
    if (set.relative()) {
      const auto r = o.relative_motion(q, qd, attached<O>(set.link, set.at), attached<O>(set.relative_to, set.relative_at));
      J = r.J;
      c = r.drift;
    } else {
      EXPECT_TRUE(set.at.E.isIdentity() && set.at.r.isZero()) << "the oracle's world rows are at the link's frame";
      J = o.jacobian(q, set.link_in(chain));
      c = o.drift(q, qd, set.link_in(chain));
    }
    rows.Jc.middleRows(k, a.cols()) = a.transpose() * J;
    rows.rhs.segment(k, a.cols()) = beta.segment(k, a.cols()) - a.transpose() * c;
    k += a.cols();
  }
  for (const model::JointCoupling& c : chain.couplings) {
    rows.Jc(k, static_cast<Eigen::Index>(c.joint - 1)) += S(1);
    rows.Jc(k, static_cast<Eigen::Index>(c.source - 1)) -= S(c.multiplier);
    ++k;
  }
  return rows;
}

}  // namespace sweepgen::test
