// Voxel keys and a flat hash table from a key to an index: what voxel filters, voxel maps and
// surfel maps share. Keys pack 21 bits per axis into the low 63 bits (+-2^20 voxels: 100 km at
// 5 cm), so no key equals the table's empty marker (all 64 bits set).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bimslam::common {

// The voxel of p for voxels of size 1 / inv_voxel.
inline Eigen::Vector3i VoxelOf(const Eigen::Vector3f& p, float inv_voxel) {
    return {static_cast<int>(std::floor(p.x() * inv_voxel)),
            static_cast<int>(std::floor(p.y() * inv_voxel)),
            static_cast<int>(std::floor(p.z() * inv_voxel))};
}

// 21 bits per axis, offset so that negative indices pack.
inline uint64_t PackVoxel(const Eigen::Vector3i& v) {
    const auto axis = [](int x) {
        return static_cast<uint64_t>(int64_t(x) + (1 << 20)) & 0x1FFFFFu;
    };
    return axis(v.x()) | (axis(v.y()) << 21) | (axis(v.z()) << 42);
}

inline uint64_t VoxelKey(const Eigen::Vector3f& p, float inv_voxel) {
    return PackVoxel(VoxelOf(p, inv_voxel));
}

// A voxel and its 6 face neighbours: where voxel maps look for the plane nearest a point.
inline const std::array<Eigen::Vector3i, 7> kVoxelAndFaceNeighbours = {
    Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(1, 0, 0),  Eigen::Vector3i(-1, 0, 0),
    Eigen::Vector3i(0, 1, 0), Eigen::Vector3i(0, -1, 0), Eigen::Vector3i(0, 0, 1),
    Eigen::Vector3i(0, 0, -1)};

// splitmix64's finaliser, so that neighbouring voxels spread over a table.
inline uint64_t MixKey(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// Open addressing with linear probing, key -> int32 index. Keys must not be kEmpty. It grows
// (rehashes) when more than half full; a caller that must not allocate reserves enough first.
class VoxelTable {
public:
    static constexpr uint64_t kEmpty = ~uint64_t(0);

    explicit VoxelTable(size_t expected = 1024) { Reserve(expected); }

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

    // The index stored for key, or -1.
    int32_t Find(uint64_t key) const {
        const size_t mask = keys_.size() - 1;
        for (size_t s = MixKey(key) & mask;; s = (s + 1) & mask) {
            if (keys_[s] == key) return values_[s];
            if (keys_[s] == kEmpty) return -1;
        }
    }
    // Stores value for key unless key is there; returns the stored index either way.
    int32_t Insert(uint64_t key, int32_t value) {
        if (2 * (size_ + 1) > keys_.size()) Rehash(keys_.size() * 2);
        const size_t mask = keys_.size() - 1;
        for (size_t s = MixKey(key) & mask;; s = (s + 1) & mask) {
            if (keys_[s] == key) return values_[s];
            if (keys_[s] == kEmpty) {
                keys_[s] = key;
                values_[s] = value;
                ++size_;
                return value;
            }
        }
    }

private:
    void Rehash(size_t cap) {
        std::vector<uint64_t> old_keys(cap, kEmpty);
        std::vector<int32_t> old_values(cap, -1);
        old_keys.swap(keys_);
        old_values.swap(values_);
        size_ = 0;
        for (size_t s = 0; s < old_keys.size(); ++s) {
            if (old_keys[s] != kEmpty) Insert(old_keys[s], old_values[s]);
        }
    }
    std::vector<uint64_t> keys_;
    std::vector<int32_t> values_;
    size_t size_ = 0;
};

}  // namespace bimslam::common
