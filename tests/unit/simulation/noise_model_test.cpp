// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "algorithms/common/status.hpp"
#include "algorithms/simulation/lidar_simulator.hpp"
#include "algorithms/simulation/measurement_math.hpp"
#include "tests/unit/simulation/simulation_fixtures.hpp"

namespace bimslam::simulation {
namespace {
namespace BIMSLAM_UNITY_ID {

using namespace fixtures;  // the shared scenes and sensors

// ---- The arithmetic (measurement_math.hpp) ----

TEST(MeasurementMath, InverseNormalCdfMatchesKnownQuantiles) {
    using detail::InverseNormalCdf;
    EXPECT_EQ(InverseNormalCdf(0.5), 0.0);
    // Phi^-1 at 0.8413447460685429 (1 sigma), 0.975, 0.999 and 1e-10, to Acklam's 1.15e-9.
    EXPECT_NEAR(InverseNormalCdf(0.8413447460685429), 1.0, 2e-9);
    EXPECT_NEAR(InverseNormalCdf(0.975), 1.959963984540054, 3e-9);
    EXPECT_NEAR(InverseNormalCdf(0.025), -1.959963984540054, 3e-9);
    EXPECT_NEAR(InverseNormalCdf(0.999), 3.090232306167813, 4e-9);
    EXPECT_NEAR(InverseNormalCdf(1e-10), -6.361340902404056, 8e-9);
    // The extreme uniforms PixelRandom can return give finite values.
    EXPECT_NEAR(InverseNormalCdf(0x1.0p-53), -8.21, 0.01);
    EXPECT_NEAR(InverseNormalCdf(1.0 - 0x1.0p-53), 8.21, 0.01);
}

TEST(MeasurementMath, PixelRandomIsAPureFunctionOfKeyPixelAndDraw) {
    const detail::PixelRandom a(7, 123), b(7, 123), c(7, 124), d(8, 123);
    EXPECT_EQ(a.Uniform(0), b.Uniform(0));
    EXPECT_EQ(a.Gaussian(), b.Gaussian());
    EXPECT_NE(a.Uniform(0), a.Uniform(1));
    EXPECT_NE(a.Uniform(0), c.Uniform(0));
    EXPECT_NE(a.Uniform(0), d.Uniform(0));
    double sum = 0;
    for (uint64_t pixel = 0; pixel < 100000; ++pixel) {
        const double x = detail::PixelRandom(1, pixel).Uniform(0);
        ASSERT_GT(x, 0.0);
        ASSERT_LT(x, 1.0);
        sum += x;
    }
    EXPECT_NEAR(sum / 100000, 0.5, 0.005);
}

TEST(MeasurementMath, PowerAndRounding) {
    EXPECT_EQ(detail::Power(4.0)(0.5), 0.0625);
    EXPECT_EQ(detail::Power(1.0)(0.3), 0.3);
    EXPECT_DOUBLE_EQ(detail::Power(2.5)(0.25), std::pow(0.25, 2.5));
    EXPECT_DOUBLE_EQ(detail::Power(0.5)(0.25), 0.5);
    EXPECT_EQ(detail::RoundNonNegative(2.5), 3.0);
    EXPECT_EQ(detail::RoundNonNegative(2.4999), 2.0);
    EXPECT_EQ(detail::RoundNonNegative(0.0), 0.0);
    EXPECT_EQ(detail::RoundNonNegative(4294967295.4), 4294967295.0);
}

// ---- Noise and dropout statistics ----

TEST(SimulateScan, RangeNoiseHasTheConfiguredSigma) {
    // A wall at 5 m, near normal incidence (within +/-5.7 deg): 16 beams over +/-1 deg.
    const Scene scene(WallAt(5.0, 0.5));
    const LidarModel model = SimpleModel(Linspace(1, -1, 16), 2048);
    NoiseModel noise = Exact();
    noise.range_sigma_m = 0.02;
    double sum = 0, sum2 = 0, within_1_sigma = 0;
    size_t n = 0;
    ScanImage img;
    for (uint64_t seed = 0; seed < 20; ++seed) {
        SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, seed, &img);
        for (int u = 0; u < model.beams(); ++u) {
            for (int v = 0; v < model.columns; ++v) {
                const uint32_t r = img.range_mm[img.Index(u, v)];
                if (r == 0) continue;
                const double truth = 5.0 / model.Direction(u, v).x();
                const double e = r * 1e-3 - truth;
                sum += e, sum2 += e * e, ++n;
                within_1_sigma += std::abs(e) < 0.02;
            }
        }
    }
    ASSERT_GT(n, 10000u);
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.001);  // 3 standard errors: 3 * 0.02 / sqrt(n) = 0.5 mm
    EXPECT_NEAR(sd, 0.02, 0.002);   // within 10 %
    EXPECT_NEAR(within_1_sigma / n, 0.6827, 0.02);  // Gaussian
}

// Beams at altitudes that hit the floor 1 m below at known ranges and incidences.
struct FloorBeams {
    std::vector<double> altitude_deg, range_m, cos_incidence;
    explicit FloorBeams(const std::vector<double>& ranges) {
        for (double r : ranges) {
            const double s = 1.0 / r;  // sin(-altitude) = height / range
            altitude_deg.push_back(-std::asin(s) * 180 / M_PI);
            range_m.push_back(r);
            cos_incidence.push_back(s);
        }
    }
};

// Dropout fraction of each beam of a floor scan (beams of one range and incidence each).
std::vector<double> DropoutPerBeam(const FloorBeams& beams, const NoiseModel& noise) {
    const Scene scene(FloorAt(-1.0, 40.0));
    const LidarModel model = SimpleModel(beams.altitude_deg, 2048);
    std::vector<double> dropped(beams.range_m.size(), 0.0);
    ScanImage img;
    for (uint64_t seed = 0; seed < 4; ++seed) {
        const ScanStats stats =
            SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, seed, &img);
        EXPECT_EQ(stats.hits, model.pixels());
        EXPECT_EQ(stats.returns + stats.dropouts, stats.hits);
        for (int u = 0; u < model.beams(); ++u) {
            for (int v = 0; v < model.columns; ++v) {
                const uint32_t r = img.range_mm[img.Index(u, v)];
                if (r != 0) {
                    EXPECT_NEAR(r * 1e-3, beams.range_m[u], 1e-3);
                }
                dropped[u] += r == 0;
            }
        }
    }
    for (double& d : dropped) d /= 4.0 * model.columns;
    return dropped;
}

TEST(SimulateScan, DropoutRisesWithIncidenceAngle) {
    // From nearly straight down (cos a = 0.98) to grazing (cos a = 0.1): p = 0.8 (1 - cos a)^1.
    const FloorBeams beams({1.02, 1.2, 1.6, 2.5, 5, 10});
    NoiseModel noise = Exact();
    noise.dropout_incidence_gain = 0.8;
    noise.dropout_incidence_exponent = 1.0;
    const std::vector<double> dropped = DropoutPerBeam(beams, noise);
    for (size_t u = 0; u < dropped.size(); ++u) {
        const double p = 0.8 * (1 - beams.cos_incidence[u]);
        EXPECT_NEAR(dropped[u], p, 0.03) << "cos a " << beams.cos_incidence[u];
        if (u > 0) {
            EXPECT_GT(dropped[u], dropped[u - 1]);
        }
    }
    EXPECT_LT(dropped.front(), 0.05);
    EXPECT_GT(dropped.back(), 0.6);
}

TEST(SimulateScan, DropoutRisesWithRange) {
    // Only the range term: p = 1.0 (r / 20 m)^1 at 1.5 ... 18 m.
    const FloorBeams beams({1.5, 3, 6, 12, 18});
    NoiseModel noise = Exact();
    noise.max_range_m = 20;
    noise.dropout_range_gain = 1.0;
    noise.dropout_range_exponent = 1.0;
    const std::vector<double> dropped = DropoutPerBeam(beams, noise);
    for (size_t u = 0; u < dropped.size(); ++u) {
        EXPECT_NEAR(dropped[u], beams.range_m[u] / 20, 0.03) << "range " << beams.range_m[u];
        if (u > 0) {
            EXPECT_GT(dropped[u], dropped[u - 1]);
        }
    }
    // The base rate alone.
    NoiseModel base = Exact();
    base.dropout_base = 0.25;
    for (double d : DropoutPerBeam(beams, base)) EXPECT_NEAR(d, 0.25, 0.03);
}

TEST(SimulateScan, MaxRangeCutsHits) {
    const Scene scene(WallAt(5.0, 0.5));
    const LidarModel model = SimpleModel(Linspace(1, -1, 16), 1024);
    NoiseModel noise = Exact();
    ScanImage img;
    noise.max_range_m = 4.99;
    ScanStats stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_EQ(stats.hits, 0u);
    for (uint32_t r : img.range_mm) ASSERT_EQ(r, 0u);
    noise.max_range_m = 5.03;  // the wall's corners are at 5.026 m
    stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_GT(stats.hits, 400u);
    EXPECT_EQ(stats.returns, stats.hits);
    // Only the near part of the wall within 5.01 m.
    noise.max_range_m = 5.01;
    const ScanStats part =
        SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_GT(part.hits, 0u);
    EXPECT_LT(part.hits, stats.hits);
    for (uint32_t r : img.range_mm) ASSERT_LE(r, 5010u);
}

TEST(SimulateScan, MinRangeRemovesCloseHits) {
    const Scene scene(WallAt(0.5, 0.2));
    const LidarModel model = SimpleModel(Linspace(1, -1, 16), 1024);
    NoiseModel noise = Exact();
    ScanImage img;
    noise.min_range_m = 0.6;
    ScanStats stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_GT(stats.hits, 100u);
    EXPECT_EQ(stats.too_close, stats.hits);
    EXPECT_EQ(stats.returns, 0u);
    for (size_t i = 0; i < img.range_mm.size(); ++i) {
        ASSERT_EQ(img.range_mm[i], 0u);
        ASSERT_EQ(img.element_id[i], kNoElement);
    }
    noise.min_range_m = 0.4;
    stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_EQ(stats.returns, stats.hits);
    EXPECT_EQ(stats.too_close, 0u);
    // Noise pushing a range below min_range also removes it: a wall at 0.5 m, min 0.5 m.
    noise.min_range_m = 0.5;
    noise.range_sigma_m = 0.01;
    stats = SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    EXPECT_GT(stats.too_close, stats.hits / 10);  // about 20 %: the wall's middle
    EXPECT_EQ(stats.returns + stats.too_close, stats.hits);
    for (uint32_t r : img.range_mm) ASSERT_TRUE(r == 0 || r >= 500) << r;
}

TEST(SimulateScan, QuantisesToTheRangeResolution) {
    const Scene scene(WallAt(5.0, 0.5));
    const LidarModel model = SimpleModel(Linspace(1, -1, 16), 1024);
    NoiseModel noise = Exact();
    noise.range_resolution_mm = 8;  // the RNG15 profiles' step
    ScanImage img;
    SimulateScan(scene, model, Eigen::Isometry3d::Identity(), noise, 0, &img);
    size_t returns = 0;
    for (int u = 0; u < model.beams(); ++u) {
        for (int v = 0; v < model.columns; ++v) {
            const uint32_t r = img.range_mm[img.Index(u, v)];
            if (r == 0) continue;
            ++returns;
            EXPECT_EQ(r % 8, 0u);
            EXPECT_LE(std::abs(r * 1e-3 - 5.0 / model.Direction(u, v).x()), 0.004 + 1e-6);
        }
    }
    EXPECT_GT(returns, 400u);
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::simulation
