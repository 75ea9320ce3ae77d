// warm_state: a warm solve starts from the last fit as it was, after a constraint change
// from each node's stored rotation, scale and SVD frame; a cold start from R = I, s = 1.
#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Geometry>

#include "constrained_grid.h"
#include "system/warm_state.h"

using namespace edgedeform;

namespace {

using Grid = test::ConstrainedGrid;

// A fit per term of `sys` that names its node: rotation about z by 0.01 * node, scale 1 + node.
LocalFit node_fit(const ConstrainedSystem& sys) {
  LocalFit fit;
  const auto T = static_cast<size_t>(sys.n_terms());
  fit.scale.resize(static_cast<Eigen::Index>(T));
  for (size_t t = 0; t < T; ++t) {
    const int node = sys.term_nodes[t];
    fit.rotation.push_back(Eigen::AngleAxisd(0.01 * node, Eigen::Vector3d::UnitZ()).toRotationMatrix());
    fit.right_vectors.push_back(Eigen::AngleAxisd(0.02 * node, Eigen::Vector3d::UnitX()).toRotationMatrix());
    fit.scale(static_cast<Eigen::Index>(t)) = 1.0 + node;
  }
  fit.energy = 7.0;
  return fit;
}

bool is_identity_fit(const LocalFit& fit, int terms) {
  if (static_cast<int>(fit.rotation.size()) != terms || fit.scale.size() != terms) return false;
  for (int t = 0; t < terms; ++t)
    if (!fit.rotation[static_cast<size_t>(t)].isIdentity(0.0) || !fit.right_vectors[static_cast<size_t>(t)].isIdentity(0.0) ||
        fit.scale(t) != 1.0)
      return false;
  return true;
}

}  // namespace

TEST(WarmState, AWarmStartTakesTheStoredFitAsItIs) {
  const Grid c(Domain::Edge);
  const ConstrainedSystem sys = c.layout(c.whole_sets);
  WarmState warm;
  EXPECT_FALSE(warm.has_fit());
  EXPECT_TRUE(is_identity_fit(warm.starting_fit(sys, true), sys.n_terms()));  // nothing stored yet

  warm.store(node_fit(sys));
  EXPECT_TRUE(warm.has_fit());
  EXPECT_TRUE(is_identity_fit(warm.starting_fit(sys, false), sys.n_terms()));  // cold
  EXPECT_TRUE(warm.has_fit());  // a cold start leaves it
  const LocalFit fit = warm.starting_fit(sys, true);
  EXPECT_FALSE(warm.has_fit());  // handed over to the solve
  EXPECT_EQ(fit.energy, 7.0);
  EXPECT_EQ(fit.scale, node_fit(sys).scale);
}

TEST(WarmState, AfterAConstraintChangeEachTermStartsFromItsNodesFit) {
  for (const Domain domain : {Domain::Edge, Domain::Primal}) {
    const Grid c(domain);
    const ConstrainedSystem part = c.layout(c.part_sets), whole = c.layout(c.whole_sets);
    ASSERT_LT(part.n_terms(), whole.n_terms());
    WarmState warm;
    warm.store(node_fit(part));
    warm.keep_per_node(part.term_nodes);  // the group is released: whole's terms renumber
    EXPECT_FALSE(warm.has_fit());

    const LocalFit fit = warm.starting_fit(whole, true);
    ASSERT_EQ(static_cast<int>(fit.rotation.size()), whole.n_terms());
    int kept = 0;
    for (size_t t = 0; t < whole.term_nodes.size(); ++t) {
      const int node = whole.term_nodes[t];
      const bool solved = std::find(part.term_nodes.begin(), part.term_nodes.end(), node) != part.term_nodes.end();
      const Eigen::Matrix3d R = solved ? Eigen::AngleAxisd(0.01 * node, Eigen::Vector3d::UnitZ()).toRotationMatrix()
                                       : Eigen::Matrix3d::Identity();
      EXPECT_EQ(fit.rotation[t], R) << "term " << t;
      EXPECT_EQ(fit.scale(static_cast<Eigen::Index>(t)), solved ? 1.0 + node : 1.0);
      kept += solved;
    }
    EXPECT_EQ(kept, part.n_terms());
    EXPECT_TRUE(is_identity_fit(warm.starting_fit(whole, false), whole.n_terms()));  // cold ignores them
  }
}

TEST(WarmState, AConstraintChangeWithoutAStoredFitKeepsNothing) {
  const Grid c(Domain::Primal);
  const ConstrainedSystem sys = c.layout(c.whole_sets);
  WarmState warm;
  warm.keep_per_node(sys.term_nodes);
  EXPECT_TRUE(is_identity_fit(warm.starting_fit(sys, true), sys.n_terms()));
}
