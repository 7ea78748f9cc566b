// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/changes/map_las.hpp"

#include <chrono>
#include <cmath>

namespace bimslam::change_detection {

uint8_t LasClass(changes::PointClass c) {
    switch (c) {
        case changes::PointClass::kModel:
            return io::kLasClassBuilding;
        case changes::PointClass::kNewObject:
            return kLasClassNewObject;
        case changes::PointClass::kTransient:
            return kLasClassTransient;
        case changes::PointClass::kMoved:
            return kLasClassMoved;
        case changes::PointClass::kUnexplained:
        case changes::PointClass::kOutside:
            return io::kLasClassUnclassified;
    }
    return io::kLasClassUnclassified;
}

double MapGpsTime(int64_t stamp_ns, const io::SessionManifest& manifest) {
    if (manifest.host_minus_sensor_ns) {
        return io::UnixNsToAdjustedGpsSeconds(stamp_ns + *manifest.host_minus_sensor_ns);
    }
    return double(stamp_ns) * 1e-9;
}

io::LasData MapLas(const changes::ChangeResult& r, const Eigen::Vector3d& origin_m,
                   const io::Session& session, uint16_t visit) {
    const size_t n = r.map.size();
    io::LasData las;
    las.adjusted_standard_gps_time = session.manifest.host_minus_sensor_ns.has_value();
    las.file_source_id = visit;
    io::SetLasCreationDate(las, std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count());
    las.xyz.resize(n);
    las.classification.resize(n);
    las.user_data.resize(n);
    las.point_source_id.assign(n, visit);
    las.gps_time.resize(n);
    io::LasExtraField distance{
        "distance", io::LasType::kFloat32, "signed distance to the model, m", 1e9, {}};
    io::LasExtraField element{"element", io::LasType::kInt32, "elements.csv index", -1, {}};
    io::LasExtraField object{"object", io::LasType::kInt32, "new object id", -1, {}};
    io::LasExtraField keyframes{"keyframes", io::LasType::kUint16, "keyframes that saw it", {}, {}};
    for (auto* f : {&distance, &element, &object, &keyframes}) f->values.resize(n);
    // The keyframes' times, once each.
    std::vector<double> times(session.keyframes.size());
    for (size_t k = 0; k < times.size(); ++k) {
        times[k] = MapGpsTime(session.keyframes[k].stamp_ns, session.manifest);
    }
    for (size_t i = 0; i < n; ++i) {
        las.xyz[i] = r.map.xyz[i].cast<double>() + origin_m;
        las.classification[i] = LasClass(r.point_class[i]);
        las.user_data[i] = uint8_t(r.point_class[i]);
        las.gps_time[i] = times.at(r.map.first_keyframe[i]);
        const float d = r.signed_distance_m[i];
        distance.values[i] = std::isfinite(d) ? d : 1e9;  // as map_bim.ply
        element.values[i] = r.element[i] == changes::kNoElement ? -1.0 : double(r.element[i]);
        object.values[i] = r.object[i];
        keyframes.values[i] = r.map.keyframes[i];
    }
    las.extra = {std::move(distance), std::move(element), std::move(object), std::move(keyframes)};
    return las;
}

}  // namespace bimslam::change_detection
