// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to algorithms/simulation: the measurement model's arithmetic (counter-based random
// numbers, the normal quantile, powers and rounding), kept free of Embree and TBB so that the unit
// tests can check it directly.
#pragma once

#include <cmath>
#include <cstdint>

namespace bimslam::simulation::detail {

inline constexpr double kDegToRad = M_PI / 180.0;

// ---- Counter-based random numbers: a pure function of (seed, pixel, draw) ----

// SplitMix64's output function (Stafford's Mix13 after a golden-ratio step): a bijective 64-bit
// mixer with full avalanche.
inline uint64_t Mix(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Acklam's approximation of the standard normal quantile for p in (0, 1): a rational function
// of p - 1/2 in the centre, of sqrt(-2 log(tail)) in the tails.
inline double InverseNormalCdf(double p) {
    static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                   -2.759285104469687e+02, 1.383577518672690e+02,
                                   -3.066479806614716e+01, 2.506628277459239e+00};
    static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                   -1.556989798598866e+02, 6.680131188771972e+01,
                                   -1.328068155288572e+01};
    static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                   -2.400758277161838e+00, -2.549732539343734e+00,
                                   4.374664141464968e+00,  2.938163982698783e+00};
    static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                   2.445134137142996e+00, 3.754408661907416e+00};
    constexpr double kLow = 0.02425;
    if (p >= kLow && p <= 1.0 - kLow) {
        const double q = p - 0.5, r = q * q;
        return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
               (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
    }
    const double q = std::sqrt(-2.0 * std::log(p < kLow ? p : 1.0 - p));
    const double x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
                     ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    return p < kLow ? x : -x;
}

// The random numbers of one pixel: draw k is output k of a SplitMix64 stream seeded with
// Mix(scan key ^ Mix(pixel index)). Nothing is shared between pixels or threads, so a pixel's
// numbers do not depend on which thread, block or packet casts it.
class PixelRandom {
public:
    PixelRandom(uint64_t scan_key, uint64_t pixel) : key_(Mix(scan_key ^ Mix(pixel))) {}

    // Uniform in (0, 1), from the top 52 bits of draw k: (k + 1/2) 2^-52 is exact, so neither 0
    // nor 1 (whose tail, 1 - p, would be 0 below) can come out.
    double Uniform(uint64_t draw) const {
        const uint64_t x = Mix(key_ + draw * 0x9E3779B97F4A7C15ull);
        return (static_cast<double>(x >> 12) + 0.5) * 0x1.0p-52;
    }

    // Standard normal from draw 1 (draw 0 is the dropout's) by inverting the normal CDF with
    // Acklam's rational approximation (relative error < 1.2e-9): one draw, no rejection loop, and
    // no log in the central 95 % (Box-Muller's log and cos were ~20 % of a scan). The largest
    // |z| from Uniform is 8.2.
    double Gaussian() const { return InverseNormalCdf(Uniform(1)); }

private:
    uint64_t key_;
};

// x^e for x in [0, 1]. By multiplication when e is a small integer (the defaults 4 and 2):
// std::pow was a quarter of a scan's time.
class Power {
public:
    explicit Power(double e) : e_(e), n_(e == std::floor(e) && e >= 1 && e <= 16 ? int(e) : 0) {}
    double operator()(double x) const {
        if (n_ == 0) return std::pow(x, e_);
        double y = x;
        for (int k = 1; k < n_; ++k) y *= x;
        return y;
    }

private:
    double e_;
    int n_;
};

// round(x) for 0 <= x < 2^62, inline (std::round is a libm call without SSE4.1). Ties round up,
// as std::round does for positive numbers.
inline double RoundNonNegative(double x) {
    return static_cast<double>(static_cast<int64_t>(x + 0.5));
}

}  // namespace bimslam::simulation::detail
