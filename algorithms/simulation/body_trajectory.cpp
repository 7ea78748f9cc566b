// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "algorithms/simulation/body_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "algorithms/common/polyline.hpp"
#include "algorithms/common/se3.hpp"
#include "algorithms/common/status.hpp"
#include "algorithms/simulation/measurement_math.hpp"

namespace bimslam::simulation {
namespace {
using common::StatusCode;

constexpr double kGravity = 9.80665;
using detail::kDegToRad;
constexpr double kResampleM = 0.05;    // path resampling step
constexpr double kSampleS = 0.01;      // planar samples and spline knots: 100 Hz
constexpr double kSmoothSigmaS = 0.1;  // Gaussian smoothing of the planar samples
constexpr double kDiffS = 5e-4;        // central differences
constexpr double kWobbleHz[3] = {0.31, 0.53, 0.87};

// common::Require that also rejects a NaN or infinite value, whatever `ok` says.
void RequireFinite(bool ok, const char* type, const char* field, double value, const char* rule) {
    common::Require(ok && std::isfinite(value), type, field, value, rule);
}

// Uniform cubic B-spline basis at f in [0, 1) (and its derivatives), for control points
// i-1, i, i+1, i+2.
std::array<double, 4> Basis(double f, int derivative) {
    const double f2 = f * f, f3 = f2 * f;
    switch (derivative) {
        case 0:
            return {(1 - 3 * f + 3 * f2 - f3) / 6, (4 - 6 * f2 + 3 * f3) / 6,
                    (1 + 3 * f + 3 * f2 - 3 * f3) / 6, f3 / 6};
        case 1:
            return {(-3 + 6 * f - 3 * f2) / 6, (-12 * f + 9 * f2) / 6, (3 + 6 * f - 9 * f2) / 6,
                    3 * f2 / 6};
        default:
            return {(6 - 6 * f) / 6, (-12 + 18 * f) / 6, (6 - 18 * f) / 6, 6 * f / 6};
    }
}

}  // namespace

void PathTiming::Validate() const {
    RequireFinite(speed_mps > 0 && speed_mps <= 5, "PathTiming", "speed_mps", speed_mps,
                  "must be in (0, 5] m/s");
    RequireFinite(max_accel_mps2 > 0, "PathTiming", "max_accel_mps2", max_accel_mps2,
                  "must be > 0");
    RequireFinite(max_yaw_rate_radps > 0, "PathTiming", "max_yaw_rate_radps", max_yaw_rate_radps,
                  "must be > 0");
    RequireFinite(max_lateral_accel_mps2 > 0, "PathTiming", "max_lateral_accel_mps2",
                  max_lateral_accel_mps2, "must be > 0");
    RequireFinite(stand_s >= 0, "PathTiming", "stand_s", stand_s, "must be >= 0");
}

GaitConfig GaitConfig::Go1Trot() { return GaitConfig{}; }

GaitConfig GaitConfig::Handheld() {
    GaitConfig g;
    g.base_height_m = 1.2;
    g.frequency_hz = 0.9;  // 1.8 steps per second, two steps per cycle
    g.bounce_m = 0.02;     // the head and hands bob once per step
    g.sway_m = 0.015;      // the body shifts over each stance foot
    g.roll_deg = 1.5;
    g.pitch_deg = 1.0;
    g.yaw_deg = 2.0;  // shoulders twist with the stride
    g.duty_factor = 0.6;
    g.wobble_deg = 0.5;
    g.stair_pitch_share = 0.5;
    return g;
}

GaitConfig GaitConfig::Vehicle() {
    GaitConfig g;
    g.base_height_m = 1.5;
    g.frequency_hz = 1.2;  // the body's heave and pitch modes on the suspension (1-1.5 Hz)
    g.bounce_m = 0.003;
    g.sway_m = 0.0;
    g.roll_deg = 0.3;
    g.pitch_deg = 0.3;
    g.yaw_deg = 0.0;
    g.duty_factor = 0.99;  // wheels: always on the ground (only the Go1's CAN log reads contacts)
    g.wobble_deg = 0.0;
    return g;
}

void GaitConfig::Validate() const {
    RequireFinite(base_height_m > 0 && base_height_m < 3, "GaitConfig", "base_height_m",
                  base_height_m, "must be in (0, 3) m");
    RequireFinite(frequency_hz > 0 && frequency_hz <= 5, "GaitConfig", "frequency_hz", frequency_hz,
                  "must be in (0, 5] Hz");
    RequireFinite(bounce_m >= 0 && bounce_m < 0.2, "GaitConfig", "bounce_m", bounce_m,
                  "must be in [0, 0.2) m");
    RequireFinite(sway_m >= 0 && sway_m < 0.2, "GaitConfig", "sway_m", sway_m,
                  "must be in [0, 0.2) m");
    for (const auto& [name, v] : {std::pair{"roll_deg", roll_deg},
                                  {"pitch_deg", pitch_deg},
                                  {"yaw_deg", yaw_deg},
                                  {"wobble_deg", wobble_deg}}) {
        RequireFinite(v >= 0 && v <= 20, "GaitConfig", name, v, "must be in [0, 20] deg");
    }
    RequireFinite(stair_pitch_share >= 0 && stair_pitch_share <= 1, "GaitConfig",
                  "stair_pitch_share", stair_pitch_share, "must be in [0, 1]");
    RequireFinite(duty_factor > 0 && duty_factor < 1, "GaitConfig", "duty_factor", duty_factor,
                  "must be in (0, 1)");
}

namespace {

// Heading along the path, unwrapped, averaged over half a metre.
std::vector<double> Headings(const std::vector<Eigen::Vector2d>& path, double start_yaw) {
    const size_t n = path.size();
    std::vector<double> raw(n, start_yaw), heading(n, start_yaw);
    for (size_t i = 0; i < n && n > 1; ++i) {
        const Eigen::Vector2d d = path[std::min(i + 1, n - 1)] - path[i ? i - 1 : 0];
        double a = std::atan2(d.y(), d.x());
        const double previous = i ? raw[i - 1] : start_yaw;
        raw[i] = previous + std::remainder(a - previous, 2 * M_PI);
    }
    const int half = 5;  // 0.25 m each side
    for (size_t i = 0; i < n; ++i) {
        double sum = 0;
        int count = 0;
        for (long j = long(i) - half; j <= long(i) + half; ++j) {
            if (j < 0 || j >= long(n)) continue;
            sum += raw[size_t(j)];
            ++count;
        }
        heading[i] = n > 1 ? sum / count : start_yaw;
    }
    return heading;
}

// Speed limits (and a point's own cap), then acceleration limits forwards and backwards (file
// comment, step 1). ds[i] is the step from point i - 1.
std::vector<double> Speeds(const std::vector<Eigen::Vector2d>& path,
                           const std::vector<double>& heading, const std::vector<double>& cap,
                           const PathTiming& timing, std::vector<double>* ds_out) {
    const size_t n = path.size();
    std::vector<double> ds(n, 0.0), v(n, timing.speed_mps);
    for (size_t i = 1; i < n; ++i) ds[i] = (path[i] - path[i - 1]).norm();
    for (size_t i = 0; i < n; ++i) {
        const size_t a = i ? i - 1 : 0, b = std::min(i + 1, n - 1);
        const double arc = (b > i ? ds[b] : 0) + (i > a ? ds[i] : 0);
        const double kappa = arc > 0 ? std::abs(heading[b] - heading[a]) / arc : 0;
        if (kappa > 1e-9) {
            v[i] = std::min({v[i], timing.max_yaw_rate_radps / kappa,
                             std::sqrt(timing.max_lateral_accel_mps2 / kappa)});
        }
        if (!cap.empty() && cap[i] > 0) v[i] = std::min(v[i], cap[i]);
        v[i] = std::max(v[i], 0.02);  // a turn on the spot still creeps forward
    }
    v.front() = 0;
    v.back() = 0;
    for (size_t i = 1; i < n; ++i) {
        v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * timing.max_accel_mps2 * ds[i]));
    }
    for (size_t i = n - 1; i-- > 0;) {
        v[i] =
            std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * timing.max_accel_mps2 * ds[i + 1]));
    }
    *ds_out = std::move(ds);
    return v;
}

// Timed keyframes: (x, y, yaw) and the profile (floor z, climb, flight).
struct Key {
    double t;
    Eigen::Vector3d q;
    Eigen::Vector3d profile = Eigen::Vector3d::Zero();
};

// 100 Hz samples of the keys (linear between them), Gaussian-smoothed: the spline's control
// points. `field` picks q or profile.
std::vector<Eigen::Vector3d> SmoothSamples(const std::vector<Key>& keys, double duration_s,
                                           Eigen::Vector3d Key::*field) {
    const size_t samples = size_t(std::ceil(duration_s / kSampleS)) + 1;
    std::vector<Eigen::Vector3d> raw_samples(samples);
    size_t k = 1;
    for (size_t s = 0; s < samples; ++s) {
        const double ts = std::min(double(s) * kSampleS, duration_s);
        while (k + 1 < keys.size() && keys[k].t < ts) ++k;
        const Key& a = keys[k - 1];
        const Key& b = keys.size() > 1 ? keys[k] : keys[0];
        const double span = b.t - a.t;
        const double f = span > 0 ? std::clamp((ts - a.t) / span, 0.0, 1.0) : 1.0;
        raw_samples[s] = a.*field + f * (b.*field - a.*field);
    }
    const int radius = int(std::ceil(3 * kSmoothSigmaS / kSampleS));
    std::vector<double> weights(size_t(2 * radius + 1));
    for (int j = -radius; j <= radius; ++j) {
        const double x = j * kSampleS / kSmoothSigmaS;
        weights[size_t(j + radius)] = std::exp(-0.5 * x * x);
    }
    std::vector<Eigen::Vector3d> control(samples, Eigen::Vector3d::Zero());
    for (size_t s = 0; s < samples; ++s) {
        double wsum = 0;
        for (int j = -radius; j <= radius; ++j) {
            const long idx = std::clamp(long(s) + j, 0L, long(samples) - 1);  // held at the ends
            control[s] += weights[size_t(j + radius)] * raw_samples[size_t(idx)];
            wsum += weights[size_t(j + radius)];
        }
        control[s] /= wsum;
    }
    return control;
}

// Points every kResampleM along the path in plan, each attribute interpolated linearly by the
// distance along it; the last point kept.
void ResampleAttributed(const std::vector<PathPoint>& in, std::vector<Eigen::Vector2d>* xy,
                        std::vector<Eigen::Vector3d>* profile, std::vector<double>* cap) {
    auto attributes = [](const PathPoint& p) {
        return Eigen::Vector4d(p.p.z(), p.climb_rad, p.flight, p.max_speed_mps);
    };
    auto emit = [&](const Eigen::Vector2d& q, const Eigen::Vector4d& a) {
        xy->push_back(q);
        profile->emplace_back(a[0], a[1], a[2]);
        cap->push_back(a[3]);
    };
    emit(in[0].p.head<2>(), attributes(in[0]));
    double carried = 0;  // distance walked since the last emitted point
    for (size_t i = 1; i < in.size(); ++i) {
        const Eigen::Vector2d a = in[i - 1].p.head<2>(), b = in[i].p.head<2>();
        const double len = (b - a).norm();
        double s = kResampleM - carried;
        for (; s <= len; s += kResampleM) {
            const double f = len > 0 ? s / len : 1.0;
            emit(a + f * (b - a),
                 attributes(in[i - 1]) + f * (attributes(in[i]) - attributes(in[i - 1])));
        }
        carried = len - (s - kResampleM);
    }
    if ((xy->back() - in.back().p.head<2>()).norm() > 1e-9) {
        emit(in.back().p.head<2>(), attributes(in.back()));
    }
}

}  // namespace

BodyTrajectory::BodyTrajectory(const std::vector<Eigen::Vector2d>& path_in, double start_yaw,
                               double floor_z, const PathTiming& timing, const GaitConfig& gait,
                               uint64_t seed)
    : gait_(gait), floor_z_(floor_z) {
    timing.Validate();
    gait.Validate();
    RequireFinite(std::isfinite(start_yaw), "BodyTrajectory", "start_yaw", start_yaw,
                  "must be finite");
    RequireFinite(std::isfinite(floor_z), "BodyTrajectory", "floor_z", floor_z, "must be finite");
    std::vector<Eigen::Vector2d> path;
    for (const Eigen::Vector2d& p : path_in) {
        if (!p.allFinite()) {
            throw common::Error(StatusCode::kInvalidArgument,
                                "BodyTrajectory: a path point is not finite");
        }
        if (path.empty() || (p - path.back()).norm() > 1e-9) path.push_back(p);
    }
    if (path.empty())
        throw common::Error(StatusCode::kInvalidArgument, "BodyTrajectory: empty path");
    Resampled r;
    r.xy = common::ResamplePolyline(path, kResampleM, /*closed=*/false);
    Build(r, start_yaw, timing, seed);
}

BodyTrajectory::BodyTrajectory(const std::vector<PathPoint>& path_in, double start_yaw,
                               const PathTiming& timing, const GaitConfig& gait, uint64_t seed)
    : gait_(gait) {
    timing.Validate();
    gait.Validate();
    RequireFinite(std::isfinite(start_yaw), "BodyTrajectory", "start_yaw", start_yaw,
                  "must be finite");
    std::vector<PathPoint> path;
    for (const PathPoint& p : path_in) {
        if (!p.p.allFinite() || !std::isfinite(p.climb_rad) || !std::isfinite(p.flight) ||
            !std::isfinite(p.max_speed_mps)) {
            throw common::Error(StatusCode::kInvalidArgument,
                                "BodyTrajectory: a path point is not finite");
        }
        if (path.empty() || (p.p - path.back().p).norm() > 1e-9) path.push_back(p);
    }
    if (path.empty())
        throw common::Error(StatusCode::kInvalidArgument, "BodyTrajectory: empty path");
    floor_z_ = path.front().p.z();
    Resampled r;
    ResampleAttributed(path, &r.xy, &r.profile, &r.max_speed);
    Build(r, start_yaw, timing, seed);
}

void BodyTrajectory::Build(const Resampled& r, double start_yaw, const PathTiming& timing,
                           uint64_t seed) {
    const std::vector<Eigen::Vector2d>& path = r.xy;
    const size_t n = path.size();
    const std::vector<double> heading = Headings(path, start_yaw);
    std::vector<double> ds;
    const std::vector<double> v = Speeds(path, heading, r.max_speed, timing, &ds);
    const bool flat = r.profile.empty();
    auto profile = [&](size_t i) { return flat ? Eigen::Vector3d::Zero() : r.profile[i]; };

    // Timed keyframes: stand, turn on the spot, walk, stand.
    std::vector<Key> keys;
    double t = 0;
    const Eigen::Vector3d first(path[0].x(), path[0].y(), start_yaw);
    keys.push_back({t, first, profile(0)});
    t += timing.stand_s;
    keys.push_back({t, first, profile(0)});
    const double turn = heading[0] - start_yaw;
    if (std::abs(turn) > 1e-6) {
        // Eased (raised cosine): peak rate = pi/2 * mean rate, kept at the limit.
        const double T = M_PI_2 * std::abs(turn) / timing.max_yaw_rate_radps;
        for (int k = 1; k <= 20; ++k) {
            const double f = 0.5 - 0.5 * std::cos(M_PI * k / 20.0);
            keys.push_back({t + T * k / 20.0,
                            Eigen::Vector3d(first.x(), first.y(), start_yaw + f * turn),
                            profile(0)});
        }
        t += T;
    }
    for (size_t i = 1; i < n; ++i) {
        const double mean_v = 0.5 * (v[i - 1] + v[i]);
        const double dt =
            std::max(ds[i] / std::max(mean_v, 1e-3),
                     std::abs(heading[i] - heading[i - 1]) / timing.max_yaw_rate_radps);
        t += dt;
        if (timing.start_at_speed && start_s_ == 0 && v[i] >= 0.95 * timing.speed_mps) start_s_ = t;
        length_m_ += ds[i];
        keys.push_back({t, Eigen::Vector3d(path[i].x(), path[i].y(), heading[i]), profile(i)});
    }
    t += timing.stand_s;
    keys.push_back({t, keys.back().q, keys.back().profile});
    duration_s_ = t;

    control_ = SmoothSamples(keys, duration_s_, &Key::q);
    if (!flat) profile_ = SmoothSamples(keys, duration_s_, &Key::profile);
    knot_s_ = kSampleS;

    // Wobble phases from the seed, so that runs are reproducible.
    const detail::PixelRandom random(seed, 0);
    for (size_t j = 0; j < wobble_phase_.size(); ++j)
        wobble_phase_[j] = 2 * M_PI * random.Uniform(j);
}

Eigen::Vector3d BodyTrajectory::SplineAt(double t, int derivative) const {
    const double u = std::clamp(t, 0.0, duration_s_) / knot_s_;
    const long i = std::min(long(std::floor(u)), long(control_.size()) - 1);
    const double f = u - double(i);
    const std::array<double, 4> b = Basis(f, derivative);
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) {
        const long idx = std::clamp(i - 1 + j, 0L, long(control_.size()) - 1);
        out += b[size_t(j)] * control_[size_t(idx)];
    }
    return derivative == 0 ? out : out / std::pow(knot_s_, derivative);
}

Eigen::Vector3d BodyTrajectory::ProfileAt(double t) const {
    if (profile_.empty()) return Eigen::Vector3d(floor_z_, 0, 0);
    const double u = std::clamp(t, 0.0, duration_s_) / knot_s_;
    const long i = std::min(long(std::floor(u)), long(profile_.size()) - 1);
    const std::array<double, 4> b = Basis(u - double(i), 0);
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) {
        out +=
            b[size_t(j)] * profile_[size_t(std::clamp(i - 1 + j, 0L, long(profile_.size()) - 1))];
    }
    return out;
}

double BodyTrajectory::FloorZAt(double t) const { return ProfileAt(t + start_s_).x(); }

double BodyTrajectory::FlightAt(double t) const { return ProfileAt(t + start_s_).z(); }

Eigen::Isometry3d BodyTrajectory::Pose(double t) const {
    t += start_s_;
    const Eigen::Vector3d q = SplineAt(t, 0);
    const double phase = 2 * M_PI * gait_.frequency_hz * t;
    const double deg = kDegToRad;
    double roll = gait_.roll_deg * deg * std::sin(phase);
    double pitch = gait_.pitch_deg * deg * std::sin(2 * phase + 0.7);
    double yaw = gait_.yaw_deg * deg * std::sin(phase + 1.3);
    if (gait_.wobble_deg > 0) {
        double* angles[3] = {&roll, &pitch, &yaw};
        for (int axis = 0; axis < 3; ++axis) {
            for (int j = 0; j < 3; ++j) {
                *angles[axis] +=
                    gait_.wobble_deg * deg *
                    std::sin(2 * M_PI * kWobbleHz[j] * t + wobble_phase_[size_t(3 * axis + j)]);
            }
        }
    }
    // Lowest at mid-stance: the bounce is a cosine of twice the phase.
    double bounce = gait_.bounce_m * std::cos(2 * phase);
    const double sway = gait_.sway_m * std::sin(phase);
    double floor_z = floor_z_;
    if (!profile_.empty()) {
        // On a flight: the steps replace the bounce, the body pitches with the flight.
        const Eigen::Vector3d p = ProfileAt(t);
        floor_z = p.x();
        pitch -= gait_.stair_pitch_share * p.y();
        bounce *= 1.0 - std::clamp(p.z(), 0.0, 1.0);
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << q.x(), q.y(), floor_z + gait_.base_height_m + bounce;
    T.linear() = (Eigen::AngleAxisd(q.z() + yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() += T.linear() * Eigen::Vector3d(0, sway, 0);
    return T;
}

BodyTrajectory::Planar BodyTrajectory::PlanarAt(double t) const {
    t += start_s_;
    const Eigen::Vector3d q = SplineAt(t, 0), dq = SplineAt(t, 1);
    Planar p;
    p.xy = q.head<2>();
    p.yaw = q.z();
    const bool inside = t > 0 && t < duration_s_;
    p.v_xy = inside ? Eigen::Vector2d(dq.head<2>()) : Eigen::Vector2d::Zero();
    p.yaw_rate = inside ? dq.z() : 0.0;
    return p;
}

FootContacts BodyTrajectory::ContactsAt(double t) const {
    // Trot: FR with RL, FL with RR, half a cycle apart; each foot on the ground duty_factor of
    // its cycle, starting at its pair's phase.
    const double cycle = (t + start_s_) * gait_.frequency_hz;
    auto on = [&](double offset) {
        const double phase = cycle + offset - std::floor(cycle + offset);
        return phase < gait_.duty_factor;
    };
    return {on(0.0), on(0.5), on(0.5), on(0.0)};
}

BodyTrajectory::Kinematics BodyTrajectory::KinematicsAt(
    double t, const Eigen::Isometry3d& T_base_frame) const {
    const double h = kDiffS;
    const Eigen::Isometry3d Tm = Pose(t - h) * T_base_frame;
    const Eigen::Isometry3d T0 = Pose(t) * T_base_frame;
    const Eigen::Isometry3d Tp = Pose(t + h) * T_base_frame;
    Kinematics k;
    k.T_world_frame = T0;
    k.v_world = (Tp.translation() - Tm.translation()) / (2 * h);
    k.a_world = (Tp.translation() - 2 * T0.translation() + Tm.translation()) / (h * h);
    // Body rate: R(t+h) = R(t-h) Exp(2h omega) to second order.
    k.omega_frame = common::LogSO3(Tm.linear().transpose() * Tp.linear()) / (2 * h);
    k.specific_force_frame =
        T0.linear().transpose() * (k.a_world - Eigen::Vector3d(0, 0, -kGravity));
    return k;
}

}  // namespace bimslam::simulation
