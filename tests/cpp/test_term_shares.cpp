#include <gtest/gtest.h>

#include "mesh/stiffness.h"
#include "local_fit/term_shares.h"

using namespace edgedeform;

TEST(TermShares, TheThreeSharesSumToOneAndFollowLambdaAndTheFloor) {
  for (double lambda : {0.0, 0.004, 0.3, 1.0}) {
    const Eigen::VectorXd phi = similarity_share(Eigen::VectorXd::Constant(1, lambda), kPrimalSimilarityFloor);
    const TermShares s = term_shares(lambda, phi(0));
    EXPECT_DOUBLE_EQ(s.rigid + s.similar + s.smooth, 1.0);
    EXPECT_EQ(s.rigid, lambda);
    EXPECT_EQ(s.one_form(), lambda + phi(0));
    EXPECT_GE(s.smooth, 0.0);
  }
  EXPECT_EQ(term_shares(1.0, 0.0).smooth, 0.0);  // lambda 1: the rigid 1-form term alone
  EXPECT_EQ(term_shares(0.0, 0.01).similar, 0.01);
}
