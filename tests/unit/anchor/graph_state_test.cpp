// The model's tolerance added to a loop's information (host_tools/anchor/graph_state.hpp).
#include "host_tools/anchor/graph_state.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

namespace bimslam::anchor {
namespace {
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Matrix6d Spd(unsigned seed) {
    std::srand(seed);
    const Matrix6d a = Matrix6d::Random();
    return a * a.transpose() * 1e4 + Matrix6d::Identity() * 100;
}

TEST(ModelTolerance, FullRankIsTheInverseOfTheSummedCovariances) {
    const Matrix6d h = Spd(3);
    const double sm = 0.02, sd = 0.2, sr = sd * M_PI / 180;
    Eigen::Matrix<double, 6, 1> v;
    v << sm * sm, sm * sm, sm * sm, sr * sr, sr * sr, sr * sr;
    const Matrix6d expected = (h.inverse() + Matrix6d(v.asDiagonal())).inverse();
    const Matrix6d got = WithModelTolerance(h, sm, sd);
    EXPECT_LT((got - expected).norm() / expected.norm(), 1e-9);
    // Less information than before in every direction.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(h - got).eigenvalues().minCoeff(), -1e-9);
}

TEST(ModelTolerance, ZeroToleranceKeepsTheInformation) {
    const Matrix6d h = Spd(5);
    EXPECT_LT((WithModelTolerance(h, 0, 0) - h).norm(), 1e-9 * h.norm());
}

TEST(ModelTolerance, UnconstrainedDirectionsStayWithoutInformation) {
    // A corridor: the registration constrained everything but x.
    Matrix6d h = Spd(7);
    h.row(0).setZero();
    h.col(0).setZero();
    const Matrix6d got = WithModelTolerance(h, 0.02, 0.2);
    EXPECT_LT(got.row(0).norm(), 1e-9 * got.norm());
    EXPECT_LT(got.col(0).norm(), 1e-9 * got.norm());
    // The constrained block is the full-rank formula on it.
    const Eigen::Matrix<double, 5, 5> hb = h.bottomRightCorner<5, 5>();
    Eigen::Matrix<double, 5, 1> v;
    const double sr = 0.2 * M_PI / 180;
    v << 4e-4, 4e-4, sr * sr, sr * sr, sr * sr;
    const Eigen::Matrix<double, 5, 5> expected =
        (hb.inverse() + Eigen::Matrix<double, 5, 5>(v.asDiagonal())).inverse();
    EXPECT_LT((got.bottomRightCorner<5, 5>() - expected).norm() / expected.norm(), 1e-9);
}

}  // namespace
}  // namespace bimslam::anchor
