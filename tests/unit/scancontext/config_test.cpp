// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/scancontext/config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "algorithms/common/status.hpp"

namespace bimslam::scancontext {
namespace {
namespace BIMSLAM_UNITY_ID {

TEST(ScanContextConfigTest, OutdoorDefaultsFollowThePaper) {
    const ScanContextConfig c = ScanContextConfig::Outdoor();
    EXPECT_EQ(c.kind, DescriptorKind::kOutdoor);
    EXPECT_EQ(c.num_rings, 20);
    EXPECT_EQ(c.num_sectors, 60);
    EXPECT_DOUBLE_EQ(c.max_radius, 80.0);
    EXPECT_DOUBLE_EQ(c.lidar_height, 2.0);
    EXPECT_EQ(c.num_candidates, 10);
    EXPECT_DOUBLE_EQ(c.search_ratio, 0.1);
    EXPECT_NEAR(c.SectorAngle(), 6.0 * M_PI / 180.0, 1e-15);
    EXPECT_DOUBLE_EQ(c.RingWidth(), 4.0);
    EXPECT_NO_THROW(c.Validate());
    EXPECT_EQ(ScanContextConfig{}.kind, DescriptorKind::kOutdoor);
}

TEST(ScanContextConfigTest, IndoorDefaults) {
    const ScanContextConfig c = ScanContextConfig::Indoor();
    EXPECT_EQ(c.kind, DescriptorKind::kIndoor);
    EXPECT_EQ(c.num_rings, 20);
    EXPECT_EQ(c.num_sectors, 60);
    EXPECT_DOUBLE_EQ(c.max_radius, 10.0);
    EXPECT_EQ(c.indoor_min_points, 3);
    EXPECT_DOUBLE_EQ(c.indoor_min_z_span, 0.3);
    EXPECT_NO_THROW(c.Validate());
}

TEST(ScanContextConfigTest, KindNamesRoundTrip) {
    for (DescriptorKind k : {DescriptorKind::kOutdoor, DescriptorKind::kIndoor}) {
        EXPECT_EQ(ParseDescriptorKind(ToString(k)), k);
    }
    EXPECT_EQ(ToString(DescriptorKind::kIndoor), "indoor");
    EXPECT_FALSE(ParseDescriptorKind("Indoor").has_value());
    EXPECT_FALSE(ParseDescriptorKind("").has_value());
}

// Expects Validate() to throw common::Error whose message names the field and the value.
void ExpectInvalid(const std::function<void(ScanContextConfig&)>& change, const std::string& field,
                   const std::string& value) {
    ScanContextConfig c = ScanContextConfig::Outdoor();
    change(c);
    try {
        c.Validate();
        ADD_FAILURE() << "no error for " << field << " = " << value;
    } catch (const common::Error& e) {
        EXPECT_EQ(e.code(), common::StatusCode::kInvalidArgument);
        const std::string what = e.what();
        EXPECT_NE(what.find(field), std::string::npos) << what;
        EXPECT_NE(what.find("= " + value), std::string::npos) << what;
    }
}

TEST(ScanContextConfigTest, ValidateNamesTheBadFieldAndValue) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    ExpectInvalid([](auto& c) { c.kind = static_cast<DescriptorKind>(7); }, "kind", "7");
    ExpectInvalid([](auto& c) { c.num_rings = 0; }, "num_rings", "0");
    ExpectInvalid([](auto& c) { c.num_rings = 501; }, "num_rings", "501");
    ExpectInvalid([](auto& c) { c.num_sectors = 1; }, "num_sectors", "1");
    ExpectInvalid([](auto& c) { c.num_sectors = 721; }, "num_sectors", "721");
    ExpectInvalid([](auto& c) { c.max_radius = 0.0; }, "max_radius", "0");
    ExpectInvalid([](auto& c) { c.max_radius = -5.0; }, "max_radius", "-5");
    ExpectInvalid([nan](auto& c) { c.max_radius = nan; }, "max_radius", "nan");
    ExpectInvalid([inf](auto& c) { c.lidar_height = inf; }, "lidar_height", "inf");
    ExpectInvalid([](auto& c) { c.indoor_min_points = 0; }, "indoor_min_points", "0");
    ExpectInvalid([](auto& c) { c.indoor_min_z_span = -0.1; }, "indoor_min_z_span", "-0.1");
    ExpectInvalid([](auto& c) { c.num_candidates = 0; }, "num_candidates", "0");
    ExpectInvalid([](auto& c) { c.search_ratio = 1.5; }, "search_ratio", "1.5");
    ExpectInvalid([](auto& c) { c.search_ratio = -0.1; }, "search_ratio", "-0.1");
    ExpectInvalid([nan](auto& c) { c.search_ratio = nan; }, "search_ratio", "nan");
}

TEST(ScanContextConfigTest, EdgeValuesAreValid) {
    ScanContextConfig c = ScanContextConfig::Indoor();
    c.search_ratio = 0.0;
    EXPECT_NO_THROW(c.Validate());
    c.search_ratio = 1.0;
    c.num_rings = 1;
    c.num_sectors = 2;
    c.indoor_min_z_span = 0.0;
    c.lidar_height = -1.0;
    EXPECT_NO_THROW(c.Validate());
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::scancontext
