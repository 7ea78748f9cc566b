// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// libFuzzer target: Ouster packet parsing + frame batching + IMU decoding on hostile input.
// The input is a script over valid packets, so the fuzzer reaches deep batcher states without a
// corpus: byte 0 picks the profile (and header type, CRC), then each 4-byte command takes packet
// k of frame f and feeds it as is, bit-flipped, cut short, padded, or as raw input bytes.
// Run: see tests/fuzz/README.md.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "drivers/ouster/frame_batcher.hpp"
#include "drivers/ouster/imu_packet.hpp"
#include "drivers/ouster/packet_encoder.hpp"
#include "tests/support/ouster_fixtures.hpp"

namespace {
using namespace bimslam::ouster;

struct World {
    SensorInfo info;
    std::vector<std::vector<uint8_t>> frames[3];  // the packets of three consecutive frames
    std::unique_ptr<FrameBatcher> batcher;        // built once, Reset per input (speed)
};

World& WorldFor(uint8_t selector) {
    static std::vector<World> worlds = [] {
        std::vector<World> out;
        for (LidarProfile p : fixtures::kAllProfiles) {
            for (int variant = 0; variant < 2; ++variant) {
                World w;
                w.info = fixtures::MakeSensor(p, variant == 0 ? 16 : 32, 512);
                if (variant == 1) {  // a wrapping column window and FW 3 CRC footers
                    w.info.format.column_window_first = 448;
                    w.info.format.column_window_last = 63;
                }
                const PacketEncoder enc(w.info, variant == 1);
                w.batcher = std::make_unique<FrameBatcher>(w.info);
                for (uint32_t f = 0; f < 3; ++f) {
                    w.frames[f] =
                        fixtures::Encode(enc, fixtures::MakeFrame(enc.format(), 65534 + f, f));
                }
                out.push_back(std::move(w));
            }
        }
        return out;
    }();
    return worlds[selector % worlds.size()];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    World& world = WorldFor(data[0]);
    FrameBatcher& batcher = *world.batcher;
    batcher.Reset();
    ImuDecoder imu(world.info);
    ImuSample samples[8];
    std::vector<uint8_t> packet;
    size_t i = 1;
    while (i + 4 <= size) {
        const uint8_t op = data[i], frame = data[i + 1] % 3, k = data[i + 2], arg = data[i + 3];
        i += 4;
        const auto& frames = world.frames[frame];
        packet = frames[k % frames.size()];
        switch (op % 6) {
            case 0:
                break;  // as is
            case 1:
                packet[(size_t(k) * 251 + arg * 13) % packet.size()] ^= uint8_t(1 << (arg % 8));
                break;
            case 2:
                packet.resize(packet.size() * arg / 256);
                break;
            case 3:
                packet.insert(packet.end(), arg % 17, 0xFF);
                break;
            case 4: {  // raw bytes from the input, as a lidar and as an IMU packet
                const size_t n = std::min<size_t>(size - i, size_t(arg) * 40);
                packet.assign(data + i, data + i + n);
                i += n;
                imu.Decode(packet.data(), packet.size(), samples);
                break;
            }
            default: {  // overwrite a header byte with input
                if (i < size) packet[arg % std::min<size_t>(packet.size(), 48)] = data[i++];
                break;
            }
        }
        batcher.AddPacket(packet.data(), packet.size(), int64_t(i));
        for (const LidarFrame* f : batcher.ready()) {
            if (f->columns_received > f->columns_expected || f->w != 512) __builtin_trap();
        }
        const LidarStats& s = batcher.stats();
        if (s.accepted + s.TotalRejected() != s.packets) __builtin_trap();
    }
    batcher.Flush();
    return 0;
}
