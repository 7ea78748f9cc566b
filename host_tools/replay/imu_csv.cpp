// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/replay/imu_csv.hpp"

#include <cstdio>
#include <string>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/text_reader.hpp"

namespace bimslam::replay {
namespace {
constexpr const char* kHeader = "t_s,gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z";
}  // namespace

void WriteImuCsv(const std::filesystem::path& path,
                 const std::vector<odometry::ImuMeasurement>& samples) {
    std::string text = std::string(kHeader) + "\n";
    char buf[160];
    for (const odometry::ImuMeasurement& m : samples) {
        // %.9g keeps float64 gyro and accel to well below the sensor's resolution.
        std::snprintf(buf, sizeof(buf), ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", m.gyro.x(), m.gyro.y(),
                      m.gyro.z(), m.accel.x(), m.accel.y(), m.accel.z());
        text += io::FormatNsAsSeconds(m.t_ns) + buf;
    }
    io::WriteFileAtomic(path, text);
}

std::vector<odometry::ImuMeasurement> ReadImuCsv(const std::filesystem::path& path) {
    const std::string text = io::ReadFileToString(path);
    io::LineReader reader(path.string(), text);
    std::string_view line;
    if (!reader.Next(line) || line != kHeader) {
        reader.Fail(std::string("expected the header line \"") + kHeader + "\"");
    }
    std::vector<odometry::ImuMeasurement> out;
    std::string spaced;
    std::vector<std::string_view> tokens;
    while (reader.Next(line)) {
        if (line.empty()) continue;
        spaced.assign(line);
        for (char& c : spaced) c = c == ',' ? ' ' : c;
        io::LineReader::Split(spaced, tokens);
        if (tokens.size() != 7) {
            reader.Fail(std::to_string(tokens.size()) + " fields, expected 7 (" + kHeader + ")");
        }
        odometry::ImuMeasurement m;
        m.t_ns = reader.ParseSecondsToNs(tokens[0], "t_s");
        for (int k = 0; k < 3; ++k) {
            m.gyro[k] = reader.ParseDouble(tokens[1 + k], "gyro");
            m.accel[k] = reader.ParseDouble(tokens[4 + k], "accel");
        }
        if (!out.empty() && m.t_ns < out.back().t_ns) reader.Fail("t_s goes back in time");
        out.push_back(m);
    }
    return out;
}

}  // namespace bimslam::replay
