// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The metadata's enum strings (specs/ouster-lidar.md) and back.
#include "drivers/ouster/sensor_info.hpp"

#include <array>
#include <utility>

namespace bimslam::ouster {
namespace {

// The strings exactly as the sensor writes them in udp_profile_lidar / udp_profile_imu /
// header_type (the SDK's profile tables use the same spelling).
constexpr std::array<std::pair<LidarProfile, std::string_view>, 6> kLidarProfiles{{
    {LidarProfile::kLegacy, "LEGACY"},
    {LidarProfile::kRng19Rfl8Sig16Nir16, "RNG19_RFL8_SIG16_NIR16"},
    {LidarProfile::kRng15Rfl8Nir8, "RNG15_RFL8_NIR8"},
    {LidarProfile::kRng19Rfl8Sig16Nir16Dual, "RNG19_RFL8_SIG16_NIR16_DUAL"},
    {LidarProfile::kRng15Rfl8Nir8Dual, "RNG15_RFL8_NIR8_DUAL"},
    {LidarProfile::kFusaRng15Rfl8Nir8Dual, "FUSA_RNG15_RFL8_NIR8_DUAL"},
}};
constexpr std::array<std::pair<ImuProfile, std::string_view>, 2> kImuProfiles{{
    {ImuProfile::kLegacy, "LEGACY"},
    {ImuProfile::kAccel32Gyro32Nmea, "ACCEL32_GYRO32_NMEA"},
}};
constexpr std::array<std::pair<HeaderType, std::string_view>, 2> kHeaderTypes{{
    {HeaderType::kStandard, "STANDARD"},
    {HeaderType::kFusa, "FUSA"},
}};

template <typename E, size_t N>
std::string_view Name(const std::array<std::pair<E, std::string_view>, N>& table, E value) {
    for (const auto& [e, s] : table) {
        if (e == value) return s;
    }
    return "UNKNOWN";
}

template <typename E, size_t N>
std::optional<E> Lookup(const std::array<std::pair<E, std::string_view>, N>& table,
                        std::string_view s) {
    for (const auto& [e, name] : table) {
        if (name == s) return e;
    }
    return std::nullopt;
}

}  // namespace

std::string_view ToString(LidarProfile p) { return Name(kLidarProfiles, p); }
std::string_view ToString(ImuProfile p) { return Name(kImuProfiles, p); }
std::string_view ToString(HeaderType h) { return Name(kHeaderTypes, h); }

std::optional<LidarProfile> ParseLidarProfile(std::string_view s) {
    return Lookup(kLidarProfiles, s);
}
std::optional<ImuProfile> ParseImuProfile(std::string_view s) { return Lookup(kImuProfiles, s); }
std::optional<HeaderType> ParseHeaderType(std::string_view s) { return Lookup(kHeaderTypes, s); }

}  // namespace bimslam::ouster
