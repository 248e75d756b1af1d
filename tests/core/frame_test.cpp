#include "core/frame.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "core/errors.h"

namespace stickslip {
namespace {

constexpr double kRoundOff = 1e-14;

TEST(FrameFromNormal, AxisNormalsGiveTheDocumentedTangents) {
  const Eigen::Matrix3d Rx = frame_from_normal(Eigen::Vector3d(2, 0, 0));
  EXPECT_TRUE(Rx.row(0).isApprox(Eigen::RowVector3d(0, 1, 0)));
  EXPECT_TRUE(Rx.row(1).isApprox(Eigen::RowVector3d(0, 0, 1)));
  const Eigen::Matrix3d Rz = frame_from_normal(Eigen::Vector3d(0, 0, 1));
  EXPECT_TRUE(Rz.row(0).isApprox(Eigen::RowVector3d(1, 0, 0)));
  EXPECT_TRUE(Rz.row(1).isApprox(Eigen::RowVector3d(0, 1, 0)));
}

TEST(FrameFromNormal, IsARightHandedRotationForRandomNormals) {
  std::mt19937 rng(42);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d n(g(rng), g(rng), g(rng));
    const Eigen::Matrix3d R = frame_from_normal(n);
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 10 * kRoundOff);
    EXPECT_NEAR(R.determinant(), 1.0, 10 * kRoundOff);
    EXPECT_LT((R.row(2).transpose() - n.normalized()).norm(), 10 * kRoundOff);
  }
}

TEST(FrameFromNormal, HintSetsT1AndBadInputThrows) {
  const Eigen::Matrix3d R = frame_from_normal(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 1, 5));
  EXPECT_TRUE(R.row(0).isApprox(Eigen::RowVector3d(1, 1, 0).normalized()));
  EXPECT_THROW(frame_from_normal(Eigen::Vector3d::Zero()), InvalidInput);
  EXPECT_THROW(frame_from_normal(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 3)),
               InvalidInput);
}

}  // namespace
}  // namespace stickslip
