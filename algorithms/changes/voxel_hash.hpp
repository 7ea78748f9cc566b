// A hash map from 64-bit keys (packed voxel or cell coordinates) to 32-bit values, open
// addressing with linear probing: the map building, the evidence cells and the voxel meshes insert
// millions of keys, where std::unordered_map's node per entry costs several times the time and
// memory. Keys are integers the caller packs (PackVoxel); the all-ones key is reserved as empty.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace bimslam::changes {

// (x, y, z) voxel indices packed into 21 bits each (offset by 2^20): +-1 048 575 voxels per axis,
// +-52 km at 5 cm. Keys sort by x, then y, then z.
inline constexpr int64_t kVoxelIndexLimit = (1 << 20) - 1;
inline uint64_t PackVoxel(int64_t x, int64_t y, int64_t z) {
    constexpr int64_t kOffset = 1 << 20;
    return (uint64_t(x + kOffset) << 42) | (uint64_t(y + kOffset) << 21) | uint64_t(z + kOffset);
}
inline Eigen::Vector3i UnpackVoxel(uint64_t key) {
    constexpr int64_t kOffset = 1 << 20;
    constexpr uint64_t kMask = (1u << 21) - 1;
    return {int(int64_t((key >> 42) & kMask) - kOffset),
            int(int64_t((key >> 21) & kMask) - kOffset), int(int64_t(key & kMask) - kOffset)};
}
// The voxel of p for voxels of `size` metres, clamped into the packable range.
inline Eigen::Vector3i VoxelOf(const Eigen::Vector3f& p, float size) {
    Eigen::Vector3i v;
    for (int k = 0; k < 3; ++k) {
        const float f = std::floor(p[k] / size);
        v[k] = int(std::clamp(f, float(-kVoxelIndexLimit), float(kVoxelIndexLimit)));
    }
    return v;
}

class VoxelHash {
public:
    static constexpr uint64_t kEmpty = std::numeric_limits<uint64_t>::max();
    static constexpr uint32_t kAbsent = std::numeric_limits<uint32_t>::max();

    explicit VoxelHash(size_t expected = 1024) { Rehash(Capacity(expected)); }

    // The value of key, inserting `value` first when the key is new. `inserted` tells which.
    uint32_t& FindOrInsert(uint64_t key, uint32_t value, bool* inserted = nullptr) {
        if (2 * (size_ + 1) > keys_.size()) Rehash(2 * keys_.size());
        size_t i = Slot(key);
        while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & mask_;
        const bool fresh = keys_[i] == kEmpty;
        if (fresh) {
            keys_[i] = key;
            values_[i] = value;
            ++size_;
        }
        if (inserted) *inserted = fresh;
        return values_[i];
    }
    // The value of key, or kAbsent.
    uint32_t Find(uint64_t key) const {
        size_t i = Slot(key);
        while (keys_[i] != kEmpty) {
            if (keys_[i] == key) return values_[i];
            i = (i + 1) & mask_;
        }
        return kAbsent;
    }
    size_t size() const { return size_; }
    // Calls f(key, value) for every entry, in no particular order.
    template <class F>
    void ForEach(F&& f) const {
        for (size_t i = 0; i < keys_.size(); ++i) {
            if (keys_[i] != kEmpty) f(keys_[i], values_[i]);
        }
    }

private:
    static size_t Capacity(size_t expected) {
        size_t c = 16;
        while (c < 2 * expected) c *= 2;
        return c;
    }
    size_t Slot(uint64_t key) const {
        key ^= key >> 33;  // MurmurHash3's 64-bit finaliser
        key *= 0xff51afd7ed558ccdull;
        key ^= key >> 33;
        return size_t(key) & mask_;
    }
    void Rehash(size_t capacity) {
        std::vector<uint64_t> keys(capacity, kEmpty);
        std::vector<uint32_t> values(capacity, 0);
        keys.swap(keys_);
        values.swap(values_);
        mask_ = capacity - 1;
        size_ = 0;
        for (size_t i = 0; i < keys.size(); ++i) {
            if (keys[i] != kEmpty) FindOrInsert(keys[i], values[i]);
        }
    }

    std::vector<uint64_t> keys_;
    std::vector<uint32_t> values_;
    size_t mask_ = 0;
    size_t size_ = 0;
};

}  // namespace bimslam::changes
