// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The relative-pose residual of the pose graph, as a Ceres functor over quaternion (x y z w) and
// translation blocks: shared by the pose graph (pose_graph.hpp) and by the keyframes' refinement
// against the model (algorithms/changes/pose_refinement.hpp), so both read a session's edges the
// same way. Header-only and templated on the scalar; no Ceres include (the users bring it).
//
// The residual is [t; 2 vec(q)] of z^-1 * T_a^-1 * T_b (the SE(3) logarithm to first order, exact
// at zero: Ceres' pose_graph_3d example), a right perturbation of T_b, whitened by S (S^T S = the
// information over [rho; phi], SqrtInformation in pose_graph.hpp).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "algorithms/common/se3.hpp"

namespace bimslam::posegraph {

template <typename T>
using Quat = Eigen::Quaternion<T>;
template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

// [t; 2 vec(q)] of z^-1 * (qa, ta)^-1 * (qb, tb).
template <typename T>
void Relative(const Eigen::Quaterniond& qz, const Eigen::Vector3d& tz, const Quat<T>& qa,
              const Vec3<T>& ta, const Quat<T>& qb, const Vec3<T>& tb, T* r) {
    const Quat<T> qa_inv = qa.conjugate();
    const Quat<T> q_ab = qa_inv * qb;
    const Vec3<T> t_ab = qa_inv * (tb - ta);
    const Quat<T> qz_inv = qz.conjugate().cast<T>();
    Quat<T> q_err = qz_inv * q_ab;
    const Vec3<T> t_err = qz_inv * (t_ab - tz.cast<T>());
    if (q_err.w() < T(0)) q_err.coeffs() = -q_err.coeffs();  // the shorter way round
    r[0] = t_err.x();
    r[1] = t_err.y();
    r[2] = t_err.z();
    r[3] = T(2) * q_err.x();
    r[4] = T(2) * q_err.y();
    r[5] = T(2) * q_err.z();
}

template <typename T>
void Whiten(const common::Matrix6d& S, T* r) {
    T w[6];
    for (int i = 0; i < 6; ++i) {
        w[i] = T(0);
        for (int j = 0; j < 6; ++j) w[i] += S(i, j) * r[j];
    }
    for (int i = 0; i < 6; ++i) r[i] = w[i];
}

// Between two poses of one frame (odometry; a loop within one session).
struct BetweenCost {
    Eigen::Quaterniond qz;
    Eigen::Vector3d tz;
    common::Matrix6d S;
    template <typename T>
    bool operator()(const T* qa, const T* ta, const T* qb, const T* tb, T* r) const {
        Relative(qz, tz, Quat<T>(qa), Vec3<T>(ta), Quat<T>(qb), Vec3<T>(tb), r);
        Whiten(S, r);
        return true;
    }
};

// A pose as Ceres' parameter blocks: quaternion x y z w (EigenQuaternionManifold) and translation.
struct PoseBlock {
    double q[4];
    double t[3];
    void Set(const Eigen::Isometry3d& T) {
        const Eigen::Quaterniond qq = common::Rotation(T);
        q[0] = qq.x(), q[1] = qq.y(), q[2] = qq.z(), q[3] = qq.w();
        for (int i = 0; i < 3; ++i) t[i] = T.translation()(i);
    }
    Eigen::Isometry3d Get() const {
        return common::FromQuaternionTranslation(Eigen::Quaterniond(q[3], q[0], q[1], q[2]),
                                                 Eigen::Vector3d(t[0], t[1], t[2]));
    }
};

}  // namespace bimslam::posegraph
