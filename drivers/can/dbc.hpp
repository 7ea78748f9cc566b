// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Vector DBC files (CAN databases): the part of the format that drivers/can/go1_odometry.dbc, the
// single source of truth of the Go1 CAN contract (specs/go1-can.md), uses.
//
// Understood: VERSION, BU_ (nodes), VAL_TABLE_, BO_ (id, name, DLC, transmitter), SG_ (name,
// multiplexer indicator, start bit, length, byte order @1 Intel / @0 Motorola, sign, factor,
// offset, [min|max], unit, receivers), CM_ (comments are kept), VAL_ (value descriptions of a
// signal), BA_DEF_ / BA_DEF_DEF_ / BA_ (definitions, defaults and values of attributes; the values
// of GenMsgCycleTime, GenMsgTimeout and GenSigSNA are applied, the others are checked and left).
// Tolerated and skipped: NS_, BS_, and the other statements of the format (BO_TX_BU_, SIG_GROUP_,
// EV_, ENVVAR_DATA_, SGTYPE_, CAT_DEF_, FILTER, the *_REL_ attributes, SG_MUL_VAL_, ...).
// Refused: SIG_VALTYPE_ (IEEE float signals), which the codec does not implement.
//
// Bit numbering is Vector's: bit b is bit (b % 8) of byte (b / 8), bit 0 the least significant.
// An Intel (little-endian) signal's start bit is its least significant bit and its bits ascend
// through the bytes; a Motorola (big-endian) signal's start bit is its MOST significant bit and
// its bits descend within a byte and continue at bit 7 of the next byte ("sawtooth"), so that
// 7|16@0+ is a big-endian uint16 in bytes 0..1.
//
// Errors are common::FileError naming the file, the line and what is wrong, e.g.
// "go1.dbc:48: SG_ BVEL_Vx: start bit 70 + length 16 exceeds 8 bytes". Parsing is set-up work
// (exceptions and allocation allowed); the hot path uses signal_codec.hpp's precomputed tables.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bimslam::can {

enum class ByteOrder : uint8_t {
    kIntel,     // @1: little-endian, start bit = least significant bit
    kMotorola,  // @0: big-endian, start bit = most significant bit (sawtooth numbering)
};

// Raw value -> text (VAL_, VAL_TABLE_), in file order.
using DbcValueTable = std::vector<std::pair<int64_t, std::string>>;

struct DbcSignal {
    std::string name;
    std::string multiplexer;  // "" (plain), "M" (multiplexor) or "m<k>" (multiplexed; kept only)
    uint32_t start_bit = 0;   // as written (see the header comment)
    uint32_t length = 0;      // bits, 1..64
    ByteOrder byte_order = ByteOrder::kIntel;
    bool is_signed = false;  // '-': two's complement
    double factor = 1.0;     // physical = raw * factor + offset; never 0
    double offset = 0.0;
    double minimum = 0.0;  // [minimum|maximum] in physical units; [0|0] means "no range"
    double maximum = 0.0;
    std::string unit;
    std::vector<std::string> receivers;
    DbcValueTable values;  // VAL_
    std::string comment;   // CM_ SG_
    // GenSigSNA: the raw bit pattern meaning "signal not available" (BA_, or a non-zero
    // BA_DEF_DEF_ default). Absent: the codec applies the spec's rule (signal_codec.hpp).
    std::optional<uint64_t> gen_sig_sna;
    size_t line = 0;  // of its SG_

    bool HasRange() const { return minimum != 0.0 || maximum != 0.0; }
    bool operator==(const DbcSignal&) const = default;
};

struct DbcMessage {
    uint32_t id = 0;        // 11-bit, or 29-bit when extended (the DBC's bit 31 removed)
    bool extended = false;  // the DBC wrote the id with bit 31 set
    std::string name;
    uint32_t dlc = 0;  // bytes, 0..64
    std::string transmitter;
    std::vector<DbcSignal> signals;  // in file order
    std::string comment;             // CM_ BO_
    int64_t cycle_time_ms = 0;       // GenMsgCycleTime (BA_, else BA_DEF_DEF_); 0: not given
    int64_t timeout_ms = 0;          // GenMsgTimeout (BA_, else BA_DEF_DEF_); 0: not given
    size_t line = 0;                 // of its BO_

    const DbcSignal* FindSignal(std::string_view signal_name) const;
    bool operator==(const DbcMessage&) const = default;
};

enum class DbcObjectType : uint8_t { kNetwork, kNode, kMessage, kSignal, kEnvironmentVariable };
enum class DbcValueType : uint8_t { kInt, kHex, kFloat, kString, kEnum };

// BA_DEF_ plus its BA_DEF_DEF_ default.
struct DbcAttributeDefinition {
    std::string name;
    DbcObjectType object = DbcObjectType::kNetwork;
    DbcValueType type = DbcValueType::kInt;
    double minimum = 0.0;  // INT, HEX, FLOAT; [0, 0] means unlimited
    double maximum = 0.0;
    std::vector<std::string> enum_values;      // ENUM
    std::optional<std::string> default_value;  // BA_DEF_DEF_ as written (number or string text)
    size_t line = 0;
    bool operator==(const DbcAttributeDefinition&) const = default;
};

struct Dbc {
    std::string version;
    std::vector<std::string> nodes;                                   // BU_
    std::vector<std::pair<std::string, DbcValueTable>> value_tables;  // VAL_TABLE_
    std::vector<DbcMessage> messages;                                 // in file order
    std::vector<DbcAttributeDefinition> attributes;
    std::string comment;  // the network comment (CM_ "...";)

    const DbcMessage* FindMessage(uint32_t id, bool extended = false) const;
    const DbcMessage* FindMessage(std::string_view message_name) const;
    bool operator==(const Dbc&) const = default;
};

// Parses DBC text; errors name `file_name` and the line. Never crashes on garbage: anything that
// is not a valid DBC (of the part described above) is a common::FileError.
Dbc ParseDbc(std::string_view text, const std::string& file_name);

// Reads and parses a file; errors name its path.
Dbc ReadDbc(const std::filesystem::path& path);

// drivers/can/go1_odometry.dbc as it was when the program was built: generated into the build
// tree from the source file (drivers/can/CMakeLists.txt), so the DBC stays the single source of
// truth and the program needs no file at run time.
std::string_view Go1DbcText();

// Go1DbcText() parsed once, on first use (a function-local static: call it at start-up, never per
// frame). Throws common::FileError if the embedded text does not parse (a build-time mistake
// that the unit tests catch).
const Dbc& Go1Dbc();

}  // namespace bimslam::can
