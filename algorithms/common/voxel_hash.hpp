// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Voxel keys and a flat hash table from a 64-bit key to a 32-bit value: what voxel filters, the
// odometry's and registration's surfel maps and the change detection's maps, evidence cells and
// voxel meshes share. They insert up to millions of keys, where std::unordered_map's node per entry
// costs several times the time and memory.
//
// A voxel key packs 21 bits per axis (index + 2^20: +-1 048 575 voxels, +-52 km at 5 cm), x in the
// high bits, so keys sort by x, then y, then z: the cells of one (x, y) column are contiguous
// (changes::PointGrid searches them by binary search) and a key unpacks (UnpackVoxel). Bit 63 stays
// clear, so no voxel key equals the table's empty marker (all 64 bits set).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace bimslam::common {

inline constexpr int kVoxelIndexLimit = (1 << 20) - 1;

// The voxel holding a point given in voxel units, clamped into the packable range. Callers scale
// by p * inv_size (the odometry and registration: a multiply on their hot paths) or by p / size
// (the change detection): the two differ by an ulp, which near a voxel face moves a point into the
// neighbouring voxel, so each keeps the one its results were made with.
// Inside the range (every point of a cropped scan) floor is one conversion, truncation corrected
// below zero; std::floor and the clamp only outside it. The odometry keys every point of every
// scan through it (VoxelKey in its voxel filters) and every registration point at every outer
// iteration (VoxelMap::KeyOf).
inline Eigen::Vector3i VoxelOf(const Eigen::Vector3f& p_in_voxels) {
    Eigen::Vector3i v;
    for (int k = 0; k < 3; ++k) {
        const float f = p_in_voxels[k];
        if (std::abs(f) < float(kVoxelIndexLimit)) {
            v[k] = static_cast<int>(f);            // towards zero ...
            v[k] -= static_cast<float>(v[k]) > f;  // ... then down (|v| < 2^24 is exact in float)
            continue;
        }
        const float c =
            std::clamp(std::floor(f), float(-kVoxelIndexLimit), float(kVoxelIndexLimit));
        v[k] = static_cast<int>(c);  // NaN: as before, the conversion's own result
    }
    return v;
}

// 21 bits per axis, offset so that negative indices pack; x highest (see above). An index out of
// range wraps within its own 21 bits rather than spilling into another axis.
inline uint64_t PackVoxel(const Eigen::Vector3i& v) {
    const auto axis = [](int x) {
        return static_cast<uint64_t>(int64_t(x) + (1 << 20)) & 0x1FFFFFu;
    };
    return (axis(v.x()) << 42) | (axis(v.y()) << 21) | axis(v.z());
}

inline Eigen::Vector3i UnpackVoxel(uint64_t key) {
    const auto axis = [](uint64_t bits) { return int(int64_t(bits & 0x1FFFFFu) - (1 << 20)); };
    return {axis(key >> 42), axis(key >> 21), axis(key)};
}

// The key of p's voxel for voxels of size 1 / inv_voxel.
inline uint64_t VoxelKey(const Eigen::Vector3f& p, float inv_voxel) {
    return PackVoxel(VoxelOf(p * inv_voxel));
}

// A voxel and its 6 face neighbours: where voxel maps look for the plane nearest a point.
inline const std::array<Eigen::Vector3i, 7> kVoxelAndFaceNeighbours = {
    Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(1, 0, 0),  Eigen::Vector3i(-1, 0, 0),
    Eigen::Vector3i(0, 1, 0), Eigen::Vector3i(0, -1, 0), Eigen::Vector3i(0, 0, 1),
    Eigen::Vector3i(0, 0, -1)};

// splitmix64's finaliser, so that neighbouring voxels (keys differing in a few low bits of an
// axis) spread over a table.
inline uint64_t MixKey(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// Open addressing with linear probing, key -> uint32 value (an index, or bits the caller packs).
// Keys are any 64-bit integers but kEmpty. It grows (rehashes) when more than half full; a caller
// that must not allocate reserves enough first.
class VoxelHash {
public:
    static constexpr uint64_t kEmpty = std::numeric_limits<uint64_t>::max();
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();

    explicit VoxelHash(size_t expected = 1024) { Reserve(expected); }

    // Room for n keys without rehashing.
    void Reserve(size_t n) {
        size_t cap = 16;
        while (cap < 2 * n) cap <<= 1;
        if (cap > keys_.size()) Rehash(cap);
    }
    void Clear() {
        std::fill(keys_.begin(), keys_.end(), kEmpty);
        size_ = 0;
    }
    size_t size() const { return size_; }

    // The value of key, storing `value` first when the key is new; `inserted` tells which. The
    // reference holds until the next insertion.
    uint32_t& FindOrInsert(uint64_t key, uint32_t value, bool* inserted = nullptr) {
        if (2 * (size_ + 1) > keys_.size()) Rehash(2 * keys_.size());
        const size_t mask = keys_.size() - 1;
        size_t s = MixKey(key) & mask;
        while (keys_[s] != kEmpty && keys_[s] != key) s = (s + 1) & mask;
        const bool fresh = keys_[s] == kEmpty;
        if (fresh) {
            keys_[s] = key;
            values_[s] = value;
            ++size_;
        }
        if (inserted) *inserted = fresh;
        return values_[s];
    }
    // The value of key, or kAbsent.
    uint32_t Find(uint64_t key) const {
        const size_t mask = keys_.size() - 1;
        for (size_t s = MixKey(key) & mask; keys_[s] != kEmpty; s = (s + 1) & mask) {
            if (keys_[s] == key) return values_[s];
        }
        return kAbsent;
    }
    // Calls f(key, value) for every entry, in no particular order (it depends on the hash).
    template <class F>
    void ForEach(F&& f) const {
        for (size_t s = 0; s < keys_.size(); ++s) {
            if (keys_[s] != kEmpty) f(keys_[s], values_[s]);
        }
    }

private:
    void Rehash(size_t cap) {
        std::vector<uint64_t> old_keys(cap, kEmpty);
        std::vector<uint32_t> old_values(cap, 0);
        old_keys.swap(keys_);
        old_values.swap(values_);
        size_ = 0;
        for (size_t s = 0; s < old_keys.size(); ++s) {
            if (old_keys[s] != kEmpty) FindOrInsert(old_keys[s], old_values[s]);
        }
    }

    std::vector<uint64_t> keys_;
    std::vector<uint32_t> values_;
    size_t size_ = 0;
};

}  // namespace bimslam::common
