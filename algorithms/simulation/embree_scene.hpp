// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to algorithms/simulation: what a Scene holds. Only the simulation's .cpp files include
// this (it is where Embree appears).
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "algorithms/simulation/scene.hpp"

namespace bimslam::simulation {

struct Scene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<uint32_t> ids;  // per triangle (primID of geometry 0)
    // Per triangle; empty when every triangle is diffuse (the common case: no lookups then).
    std::vector<Material> materials;
    size_t triangles = 0;
    // Per triangle, for closest-point queries: its vertices and its unit normal (zero when
    // degenerate), 12 floats together: no index lookups, and the plane distance rejects most
    // triangles before the exact test (in double, from the vertices: scene.cpp).
    struct TriangleData {
        Eigen::Vector3f a, b, c, normal;
    };
    std::vector<TriangleData> triangle_data;

    // The last message Embree's error callback reported and how many it reported. The callback
    // may run on any thread (rtcGetDeviceError only sees the calling thread's error, so errors
    // raised in TBB workers while casting are only visible here); mutable because queries on a
    // const Scene may report errors.
    mutable std::mutex error_mutex;
    mutable std::string last_error;
    mutable std::atomic<uint64_t> error_count{0};

    ~Impl();
};

// Throws common::Error naming `what` and Embree's last message when Embree reported an error
// since error_count was `count_before`: a packet query Embree refuses (e.g. a build without
// EMBREE_RAY_PACKETS) must not pass for a scan of misses.
void ThrowIfEmbreeFailed(const Scene::Impl& impl, uint64_t count_before, const char* what);

}  // namespace bimslam::simulation
