#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "local_fit/rotation_fit.h"

using namespace edgedeform;

namespace {

// Reference: Eigen's general SVD and the textbook reflection fix.
Eigen::Matrix3d reference_rotation(const Eigen::Matrix3d& S) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d R = svd.matrixV() * U.transpose();
  if (R.determinant() < 0) {
    U.col(2) *= -1;
    R = svd.matrixV() * U.transpose();
  }
  return R;
}

}  // namespace

TEST(ClosestRotation, MatchesTheSvdReferenceOnRandomMatrices) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix3d S;
    for (int k = 0; k < 9; ++k) S.data()[k] = g(rng);
    const Eigen::Matrix3d R = closest_rotation(S);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT((R - reference_rotation(S)).norm(), 1e-9) << "trial " << trial;
  }
}

TEST(ClosestRotation, RecoversARotationFromARotatedRankTwoMatrix) {
  // A planar neighbourhood: S = sum w e0 e^T with every e0 in a plane.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d e0s[3] = {{1, 0, 0}, {0.3, 1, 0}, {-0.7, 0.2, 0}};
  for (const auto& e0 : e0s) S += e0 * (Q * e0).transpose();
  EXPECT_LT((closest_rotation(S) - Q).norm(), 1e-12);
}

TEST(ClosestRotation, IdentityForASymmetricPositiveMatrix) {
  Eigen::Matrix3d S;
  S << 3, 1, 0, 1, 2, 0.5, 0, 0.5, 1;
  EXPECT_LT((closest_rotation(S) - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_LT((closest_rotation(Eigen::Matrix3d::Zero()) - Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

TEST(ClosestRotation, ReflectionIsFixed) {
  Eigen::Matrix3d S = Eigen::Vector3d(3, 2, 1).asDiagonal();
  S(2, 2) = -1;  // det < 0: the best proper rotation flips the smallest axis back
  const Eigen::Matrix3d R = closest_rotation(S);
  EXPECT_LT((R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}


TEST(RotationAboutAxis, ACollinearNeighbourhoodTakesItsSpinFromTheTieBreaker) {
  // Two weighted arcs along one line (as on a right-angled grid, where the other arcs'
  // weights are clamped to 0): S only fixes the axis; the unweighted arcs fix the rest.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d line(1, 1e-9, -1), side(1, 0, 1);
  const Eigen::Matrix3d S = line * (Q * line).transpose() + (-line) * (Q * -line).transpose();
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity();
  const RotationFit fit = fit_rotation(S, V);
  ASSERT_TRUE(fit.degenerate);
  EXPECT_LT((fit.R * fit.u1 - fit.v1).norm(), 1e-12);
  const Eigen::Matrix3d tie = S + side * (Q * side).transpose();
  EXPECT_LT((rotation_about_axis(fit.u1, fit.v1, tie) - Q).norm(), 1e-12);
  // At rest (Q = I) the answer is the identity.
  const Eigen::Matrix3d rest = line * line.transpose() * 2.0;
  V.setIdentity();
  const RotationFit at_rest = fit_rotation(rest, V);
  const Eigen::Matrix3d tie_rest = rest + side * side.transpose();
  EXPECT_LT((rotation_about_axis(at_rest.u1, at_rest.v1, tie_rest) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(RotationAboutAxis, WithoutInformationItIsTheMinimalRotation) {
  const Eigen::Vector3d u = Eigen::Vector3d(1, 2, 2) / 3.0, v = Eigen::Vector3d(0, 0, 1);
  const Eigen::Matrix3d R = rotation_about_axis(u, v, Eigen::Matrix3d::Zero());
  EXPECT_LT((R * u - v).norm(), 1e-14);
  EXPECT_LT((R * u.cross(v) - u.cross(v)).norm(), 1e-14);  // the axis u x v stays put
  EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
}

TEST(RefineRotation, FromANearbyRotationReachesTheSvdOptimum) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  int refined = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Eigen::Matrix3d S;
    for (int k = 0; k < 9; ++k) S.data()[k] = g(rng);
    S += 3.0 * Eigen::Matrix3d::Identity();  // well conditioned, optimum near I
    const Eigen::Matrix3d reference = reference_rotation(S);
    Eigen::Matrix3d R = Eigen::AngleAxisd(0.05, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()) * reference;
    if (!refine_rotation(S, R)) continue;
    ++refined;
    EXPECT_LT((R - reference).norm(), 1e-12) << "trial " << trial;
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-13);
  }
  EXPECT_GT(refined, 450);  // a close start is the common case and must not fall back
}

TEST(RefineRotation, DeclinesFarStartsAndDegenerateMatrices) {
  const Eigen::Matrix3d S = Eigen::Vector3d(3, 2, 1).asDiagonal();
  Eigen::Matrix3d R = Eigen::AngleAxisd(1.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d far = R;
  EXPECT_FALSE(refine_rotation(S, R));
  EXPECT_EQ(R, far);  // untouched when declined
  const Eigen::Vector3d line(1, 2, 0.5);
  R.setIdentity();
  EXPECT_FALSE(refine_rotation(line * line.transpose(), R));  // rank 1: spin undetermined
  // fit_rotation falls back to the SVD in both cases and still gives the optimum.
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity();
  EXPECT_LT((fit_rotation(S, V, &far).R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(RefineRotation, PairGivesEachLaneTheResultOfItsOwnCall) {
  // The local step refines two terms at once; each lane must match a single call bit for
  // bit, also when the other lane declines (far start, degenerate S) or needs more steps.
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  auto random_case = [&](double angle, bool degenerate, Eigen::Matrix3d& S, Eigen::Matrix3d& R) {
    for (int k = 0; k < 9; ++k) S.data()[k] = g(rng);
    if (degenerate) {
      const Eigen::Vector3d line(g(rng), g(rng), g(rng));
      S = line * line.transpose();
    } else {
      S += 3.0 * Eigen::Matrix3d::Identity();
    }
    R = Eigen::AngleAxisd(angle, Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized()) * reference_rotation(S);
  };
  const double angles[] = {0.0, 1e-8, 1e-4, 0.05, 0.25, 1.0};
  int both_refined = 0, one_refined = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix3d S[2], start[2];
    for (int k = 0; k < 2; ++k) random_case(angles[(trial + 5 * k) % 6], (trial + k) % 11 == 0, S[k], start[k]);
    Eigen::Matrix3d single[2] = {start[0], start[1]}, pair[2] = {start[0], start[1]};
    bool refined[2];
    for (int k = 0; k < 2; ++k) refined[k] = refine_rotation(S[k], single[k]);
    const Eigen::Matrix3d* const Sp[2] = {&S[0], &S[1]};
    Eigen::Matrix3d* const Rp[2] = {&pair[0], &pair[1]};
    const int mask = refine_rotation_pair(Sp, Rp);
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(((mask >> k) & 1) != 0, refined[k]) << "trial " << trial << " lane " << k;
      EXPECT_EQ(pair[k], single[k]) << "trial " << trial << " lane " << k;  // bitwise; untouched when declined
    }
    both_refined += refined[0] && refined[1];
    one_refined += refined[0] != refined[1];
  }
  EXPECT_GT(both_refined, 50);  // both kinds of pairs occur
  EXPECT_GT(one_refined, 50);
}
