// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Scan Context distance with yaw recovery ([SC] = Kim & Kim, IROS 2018, Sec. III-B).
//
// Yaw convention. Distance(a, b) returns the yaw theta with
//     cloud_b ~= Rz(theta) * cloud_a,
// i.e. b's points are a's points rotated counter-clockwise by theta about +z. In terms of frames:
// when a and b were scanned at the same place, theta is the yaw of T_b_a (p_b = T_b_a * p_a), and
// the yaw of T_world_b minus the yaw of T_world_a is -theta. theta is a multiple of the sector
// angle, wrapped into (-pi, pi] (a half-turn is +pi). In columns: b(:, j + shift) ~= a(:, j) for
// every sector j (indices mod num_sectors), and theta = shift * 2 pi / num_sectors.
//
// All functions here are allocation-free and never throw (the per-column scratch lives on the
// stack, bounded by kMaxSectors), so they can run on the rig.
#pragma once

#include <Eigen/Core>

#include "algorithms/scancontext/descriptor.hpp"

namespace bimslam::scancontext {

struct DistanceResult {
    // [SC] eq. (6): the smallest mean (1 - cosine similarity) over the searched shifts, in [0, 2]
    // (0 = identical up to rotation; 1 = nothing in common; up to 2 only with negative cells).
    double distance = 1.0;
    // Columns b is shifted from a (see above), in (-num_sectors / 2, num_sectors / 2].
    int shift = 0;
    // shift * 2 pi / num_sectors, radians in (-pi, pi].
    double yaw = 0.0;
};

// The distance reported for descriptors that share no non-empty column pair (e.g. two empty
// scans): "nothing in common", never NaN.
inline constexpr double kNoOverlapDistance = 1.0;
// The distance reported for descriptors of different shapes, or with non-finite cells: larger than
// any real distance.
inline constexpr double kIncomparableDistance = 2.0;

// Wraps a column shift into (-num_sectors / 2, num_sectors / 2].
int WrapShift(int shift, int num_sectors);
// shift * 2 pi / num_sectors after wrapping: radians in (-pi, pi].
double ShiftToYaw(int shift, int num_sectors);

// Sector-key pre-alignment: the shift k minimising sum_j (key_a[j] - key_b[j + k])^2 (indices mod
// n), wrapped as above; the first minimum in k = 0, 1, ..., n - 1 wins ties. The reference
// implementation's fastAlignUsingVkey. Returns 0 when the sizes differ or are 0.
int AlignSectorKeys(const Eigen::VectorXf& key_a, const Eigen::VectorXf& key_b);

// [SC] eq. (5) for one shift: the mean over sectors j of the cosine distance
//     1 - <a_j, b_k> / (|a_j| |b_k|),  k = j + shift (mod num_sectors),
// where a_j is column j of a. As in the reference implementation, pairs in which either column is
// all zero are left out of the mean (an occluded or empty sector says nothing about the place);
// kNoOverlapDistance when no pair is left, kIncomparableDistance when the shapes differ.
double ColumnShiftDistance(const Descriptor& a, const Descriptor& b, int shift);

// [SC] eq. (6), sped up as in the reference implementation: pre-align with the sector keys, then
// take the minimum of ColumnShiftDistance over shifts within +/- round(0.5 * search_ratio *
// num_sectors) of the pre-aligned shift (every shift once the window covers the circle; ties go
// to the shift closest to the pre-alignment). search_ratio is clamped to [0, 1].
DistanceResult Distance(const Descriptor& a, const Descriptor& b, double search_ratio = 0.1);

}  // namespace bimslam::scancontext
