// The project's own OS1-32, for the demo and the capture simulator when no metadata file is
// given: a uniform 32-beam table over the OS1's 45 degree vertical field of view, the four
// staggered detector columns (azimuth offsets of about -4.2, -1.4, +1.4, +4.2 degrees, as OS1
// sensors report them), the OS1 beam origin offset and the spec's default transforms. Not a
// copy of any real sensor's calibration.
#pragma once

#include "drivers/ouster/sensor_info.hpp"

namespace bimslam::ouster {

// columns: 512, 1024 or 2048 (10 Hz) or 512, 1024 at 20 Hz; throws common::Error otherwise.
SensorInfo BuiltinOs1_32(LidarProfile profile = LidarProfile::kRng19Rfl8Sig16Nir16,
                         int columns = 1024, int rate_hz = 10);

}  // namespace bimslam::ouster
