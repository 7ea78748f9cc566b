// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/io/trajectory.hpp"

#include <Eigen/SVD>
#include <cmath>

#include "algorithms/common/se3.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::io {
namespace {
constexpr const char* kTumNames[] = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};

bool IsBlankOrComment(std::string_view line) {
    for (char c : line) {
        if (c == '#') return true;
        if (c != ' ' && c != '\t') return false;
    }
    return true;
}

// Nearest rotation to M (SVD), used after reading 9 decimals of a rotation matrix.
Eigen::Matrix3d Orthonormalise(const Eigen::Matrix3d& M) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
    if (R.determinant() < 0) {
        Eigen::Matrix3d U = svd.matrixU();
        U.col(2) = -U.col(2);
        R = U * svd.matrixV().transpose();
    }
    return R;
}
}  // namespace

StampedPose StampedPose::FromIsometry(int64_t stamp_ns, const Eigen::Isometry3d& T) {
    StampedPose p;
    p.stamp_ns = stamp_ns;
    p.translation = T.translation();
    p.rotation = common::Rotation(T);
    return p;
}

Eigen::Isometry3d StampedPose::Pose() const {
    return common::FromQuaternionTranslation(rotation, translation);
}

std::vector<StampedPose> ParseTum(const std::string& name, std::string_view text) {
    LineReader reader(name, text);
    std::vector<StampedPose> out;
    std::vector<std::string_view> tok;
    std::string_view line;
    while (reader.Next(line)) {
        if (IsBlankOrComment(line)) continue;
        LineReader::Split(line, tok);
        if (tok.size() != 8) {
            reader.Fail("expected 8 numbers (t x y z qx qy qz qw), found " +
                        std::to_string(tok.size()));
        }
        StampedPose p;
        p.stamp_ns = reader.ParseSecondsToNs(tok[0], kTumNames[0]);
        double v[7];
        for (int i = 0; i < 7; ++i) v[i] = reader.ParseDouble(tok[i + 1], kTumNames[i + 1]);
        const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
        if (std::abs(q.norm() - 1.0) > 1e-3) {
            reader.Fail("quaternion norm " + FormatDouble(q.norm()) + " is not 1");
        }
        if (!out.empty() && p.stamp_ns < out.back().stamp_ns) {
            reader.Fail("timestamp " + std::string(tok[0]) + " goes back in time");
        }
        p.translation = Eigen::Vector3d(v[0], v[1], v[2]);
        p.rotation = q;
        out.push_back(p);
    }
    return out;
}

std::vector<StampedPose> ReadTum(const std::filesystem::path& path) {
    const std::string text = ReadFileToString(path);
    return ParseTum(path.string(), text);
}

void AppendTumLine(std::string& out, const StampedPose& p) {
    const Eigen::Quaterniond& q = p.rotation;
    const Eigen::Vector3d& t = p.translation;
    out += FormatNsAsSeconds(p.stamp_ns);
    for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
        out += ' ';
        out += FormatDouble(v);
    }
    out += '\n';
}

std::string SerializeTum(const std::vector<StampedPose>& poses) {
    std::string out;
    for (const auto& p : poses) AppendTumLine(out, p);
    return out;
}

void WriteTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
    WriteFileAtomic(path, SerializeTum(poses));
}

std::vector<Eigen::Isometry3d> ParseKitti(const std::string& name, std::string_view text) {
    LineReader reader(name, text);
    std::vector<Eigen::Isometry3d> out;
    std::vector<std::string_view> tok;
    std::string_view line;
    while (reader.Next(line)) {
        LineReader::Split(line, tok);
        if (tok.empty()) {
            reader.Fail("empty line (KITTI pose files have one 3x4 matrix per line)");
        }
        if (tok.size() != 12) {
            reader.Fail("expected 12 numbers (row-major 3x4 matrix), found " +
                        std::to_string(tok.size()));
        }
        Eigen::Matrix<double, 3, 4> M;
        for (int i = 0; i < 12; ++i) {
            M(i / 4, i % 4) =
                reader.ParseDouble(tok[i], "m" + std::to_string(i / 4) + std::to_string(i % 4));
        }
        const Eigen::Matrix3d R = M.leftCols<3>();
        if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
            R.determinant() < 0) {
            reader.Fail("the 3x3 part is not a rotation matrix");
        }
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        // Written matrices are exact rotations already; re-orthonormalise only what is not, so
        // a round trip stays bit-exact.
        T.linear() = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-12
                         ? Orthonormalise(R)
                         : R;
        T.translation() = M.col(3);
        out.push_back(T);
    }
    return out;
}

std::vector<Eigen::Isometry3d> ReadKitti(const std::filesystem::path& path) {
    const std::string text = ReadFileToString(path);
    return ParseKitti(path.string(), text);
}

void AppendKittiLine(std::string& out, const Eigen::Isometry3d& T) {
    for (int i = 0; i < 12; ++i) {
        if (i > 0) out += ' ';
        out += FormatDouble(T.matrix()(i / 4, i % 4));
    }
    out += '\n';
}

std::string SerializeKitti(const std::vector<Eigen::Isometry3d>& poses) {
    std::string out;
    for (const auto& T : poses) AppendKittiLine(out, T);
    return out;
}

void WriteKitti(const std::filesystem::path& path, const std::vector<Eigen::Isometry3d>& poses) {
    WriteFileAtomic(path, SerializeKitti(poses));
}

}  // namespace bimslam::io
