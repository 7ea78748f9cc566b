// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The project's own Ouster sensors, for the demo and the capture simulator when no metadata file
// is given: a uniform beam table over the product's vertical field of view (OS0 90, OS1 45, OS2
// 22.5 degrees, Ouster's datasheets), the four staggered detector columns (azimuth offsets of
// about -4.2, -1.4, +1.4, +4.2 degrees, as OS1 sensors report them), the product's beam origin
// offset (OS0 27.67 mm, OS1 15.806 mm, OS2 13.762 mm) and the spec's default transforms. Not a
// copy of any real sensor's calibration.
#pragma once

#include <string>

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

// columns: 512, 1024 or 2048 (10 Hz) or 512, 1024 at 20 Hz; throws common::Error otherwise.
SensorInfo BuiltinOs1_32(LidarProfile profile = LidarProfile::kRng19Rfl8Sig16Nir16,
                         int columns = 1024, int rate_hz = 10);

// The same for `model` "OS<p>-<beams>": p 0, 1 or 2, beams 16, 32, 64 or 128 ("OS1-32" is
// BuiltinOs1_32). Throws common::Error naming the model or mode otherwise.
SensorInfo BuiltinOuster(const std::string& model,
                         LidarProfile profile = LidarProfile::kRng19Rfl8Sig16Nir16,
                         int columns = 1024, int rate_hz = 10);

}  // namespace bimslam::ouster
