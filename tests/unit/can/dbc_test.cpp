// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/dbc.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "algorithms/common/status.hpp"
#include "tests/support/test_support.hpp"

namespace bimslam::can {
namespace {
namespace BIMSLAM_UNITY_ID {

std::string SourceDbcText() {
    std::ifstream in(BIMSLAM_CAN_DBC_PATH, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(Dbc, ParsesTheGo1DbcAsTheSpecDescribesIt) {
    const Dbc& dbc = Go1Dbc();
    EXPECT_EQ(dbc.version, "bimslam go1_odometry 1.0");
    EXPECT_EQ(dbc.nodes, (std::vector<std::string>{"GO1_BRIDGE", "RIG"}));
    ASSERT_EQ(dbc.messages.size(), 10u);
    // specs/go1-can.md, "The CAN frames": id, name, cycle.
    const struct {
        uint32_t id;
        const char* name;
        int64_t cycle_ms;
    } table[] = {{0x0F0, "GO1_SYNC", 10},       {0x100, "GO1_BODY_VEL", 10},
                 {0x101, "GO1_BODY_STATE", 20}, {0x110, "GO1_IMU_GYRO", 5},
                 {0x111, "GO1_IMU_ACCEL", 5},   {0x112, "GO1_IMU_QUAT", 10},
                 {0x120, "GO1_FOOT", 10},       {0x130, "GO1_ODOM_XY", 20},
                 {0x131, "GO1_ODOM_Z_YAW", 20}, {0x140, "GO1_STATUS", 100}};
    for (const auto& row : table) {
        const DbcMessage* m = dbc.FindMessage(row.id);
        ASSERT_NE(m, nullptr) << row.name;
        EXPECT_EQ(m->name, row.name);
        EXPECT_FALSE(m->extended);
        EXPECT_EQ(m->dlc, 8u);
        EXPECT_EQ(m->transmitter, "GO1_BRIDGE");
        EXPECT_EQ(m->cycle_time_ms, row.cycle_ms) << row.name;
        EXPECT_EQ(m->timeout_ms, 3 * row.cycle_ms) << row.name;  // GenMsgTimeout = 3 x cycle
        EXPECT_EQ(dbc.FindMessage(std::string_view(row.name)), m);
        // Every frame: CRC in byte 0, counter in byte 1 bits 0..3.
        EXPECT_EQ(m->signals[0].start_bit, 0u);
        EXPECT_EQ(m->signals[0].length, 8u);
        EXPECT_EQ(m->signals[1].start_bit, 8u);
        EXPECT_EQ(m->signals[1].length, 4u);
        for (const DbcSignal& s : m->signals) {
            EXPECT_EQ(s.byte_order, ByteOrder::kIntel) << s.name;  // "All signals Intel"
            EXPECT_EQ(s.receivers, std::vector<std::string>{"RIG"}) << s.name;
        }
    }
    const DbcSignal* vx = dbc.FindMessage(0x100)->FindSignal("BVEL_Vx");
    ASSERT_NE(vx, nullptr);
    EXPECT_EQ(vx->start_bit, 16u);
    EXPECT_EQ(vx->length, 16u);
    EXPECT_TRUE(vx->is_signed);
    EXPECT_DOUBLE_EQ(vx->factor, 0.001);
    EXPECT_DOUBLE_EQ(vx->minimum, -32.767);
    EXPECT_DOUBLE_EQ(vx->maximum, 32.767);
    EXPECT_EQ(vx->unit, "m/s");
    EXPECT_EQ(vx->gen_sig_sna, 32768u);
    EXPECT_EQ(vx->comment, "HighState.velocity[0] (forward speed, body frame).");
    const DbcSignal* qx = dbc.FindMessage(0x112)->FindSignal("QUAT_X");
    EXPECT_DOUBLE_EQ(qx->factor, 1.0 / 32768);  // 3.0517578125E-005
    EXPECT_FALSE(qx->gen_sig_sna.has_value());  // the spec rule applies (signal_codec)
    EXPECT_EQ(dbc.FindMessage(0x130)->FindSignal("OXY_PosX")->gen_sig_sna, 8388608u);
    EXPECT_EQ(dbc.FindMessage(0x120)->FindSignal("FOOT_Force_RL")->gen_sig_sna, 4095u);
    EXPECT_EQ(dbc.FindMessage(0x0F0)->comment,
              "Sample time reference: one per HighState sample forwarded; pairs with other frames "
              "by equal Counter.");
    EXPECT_NE(dbc.comment.find("CRC-8/SAE-J1850"), std::string::npos);
    // Value tables.
    ASSERT_EQ(dbc.value_tables.size(), 2u);
    EXPECT_EQ(dbc.value_tables[0].first, "Go1Mode");
    EXPECT_EQ(dbc.value_tables[0].second.size(), 12u);
    const DbcSignal* state = dbc.FindMessage(0x140)->FindSignal("STS_BridgeState");
    ASSERT_EQ(state->values.size(), 4u);
    EXPECT_EQ(state->values[0], (std::pair<int64_t, std::string>{3, "FAULT"}));
    // Attribute definitions and defaults.
    EXPECT_EQ(dbc.attributes.size(), 7u);
    EXPECT_EQ(dbc.attributes[3].name, "GenMsgSendType");
    EXPECT_EQ(dbc.attributes[3].type, DbcValueType::kEnum);
    EXPECT_EQ(dbc.attributes[3].enum_values.size(), 3u);
    EXPECT_EQ(dbc.attributes[3].default_value, "Cyclic");
    EXPECT_EQ(dbc.attributes[2].object, DbcObjectType::kMessage);
}

TEST(Dbc, EmbeddedTextIsTheSourceFileAndParsesIdentically) {
    const std::string source = SourceDbcText();
    ASSERT_FALSE(source.empty()) << BIMSLAM_CAN_DBC_PATH;
    EXPECT_EQ(Go1DbcText(), source);
    const Dbc from_file = ReadDbc(BIMSLAM_CAN_DBC_PATH);
    EXPECT_TRUE(from_file == Go1Dbc());
    EXPECT_EQ(&Go1Dbc(), &Go1Dbc());  // parsed once
}

TEST(Dbc, ToleratesTheRestOfTheFormat) {
    const std::string text =
        "VERSION \"\"\r\n"
        "NS_ :\r\n\tNS_DESC_\r\n\tCM_\r\n\r\n"
        "BS_: 500 : 12,34\r\n"
        "BU_: A B\r\n"
        "BO_ 2147484672 EXT: 8 A\r\n"  // 0x80000400: extended id 0x400
        " SG_ Mux M : 0|8@1+ (1,0) [0|0] \"\" B\r\n"
        " SG_ M1 m1 : 8|16@1+ (1,0) [0|0] \"\" B\r\n"
        " SG_ M2 m2 : 8|16@1+ (1,0) [0|0] \"\" B\r\n"
        " SG_ Moto : 39|16@0- (0.5,-1) [-100|100] \"deg\" A,B\r\n"
        "BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\r\n"
        " SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\r\n"
        "BO_TX_BU_ 2147484672 : A,B;\r\n"
        "CM_ BO_ 2147484672 \"two\r\nlines; with a semicolon\";\r\n"
        "CM_ BU_ A \"node\";\r\n"
        "CM_ SG_ 3221225472 Orphan \"ignored\";\r\n"
        "BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 0;\r\n"
        "BA_DEF_ BU_ \"NodeLayer\" FLOAT -1.5 1E3;\r\n"
        "BA_DEF_ \"DBName\" STRING ;\r\n"
        "BA_DEF_DEF_ \"GenMsgCycleTime\" 100;\r\n"
        "BA_DEF_DEF_ \"NodeLayer\" 0.5;\r\n"
        "BA_DEF_DEF_ \"DBName\" \"\";\r\n"
        "BA_ \"DBName\" \"x\";\r\n"
        "BA_ \"NodeLayer\" BU_ A 2;\r\n"
        "SIG_GROUP_ 2147484672 G 1 : Mux Moto;\r\n"
        "VAL_ 2147484672 Mux 1 \"one\" 2 \"two\" ;\r\n"
        "VAL_ SomeEnvVar 0 \"off\" ;\r\n"
        "SG_MUL_VAL_ 2147484672 M1 Mux 1-1;\r\n";
    const Dbc dbc = ParseDbc(text, "t.dbc");
    ASSERT_EQ(dbc.messages.size(), 1u);
    const DbcMessage& m = dbc.messages[0];
    EXPECT_TRUE(m.extended);
    EXPECT_EQ(m.id, 0x400u);
    EXPECT_EQ(m.cycle_time_ms, 100);  // the BA_DEF_DEF_ default
    EXPECT_EQ(m.comment, "two\r\nlines; with a semicolon");
    ASSERT_EQ(m.signals.size(), 4u);
    EXPECT_EQ(m.signals[0].multiplexer, "M");
    EXPECT_EQ(m.signals[2].multiplexer, "m2");
    EXPECT_EQ(m.signals[3].byte_order, ByteOrder::kMotorola);
    EXPECT_TRUE(m.signals[3].is_signed);
    EXPECT_DOUBLE_EQ(m.signals[3].offset, -1.0);
    EXPECT_EQ(m.signals[3].receivers, (std::vector<std::string>{"A", "B"}));
    EXPECT_EQ(m.signals[0].values.size(), 2u);
    EXPECT_EQ(dbc.FindMessage(0x400, true), &m);
    EXPECT_EQ(dbc.FindMessage(0x400, false), nullptr);
}

struct BadCase {
    const char* text;
    size_t line;
    const char* detail;  // expected in the message
};

TEST(Dbc, ErrorsNameTheFileTheLineAndWhatIsWrong) {
    const std::string bo = "VERSION \"\"\nBO_ 256 M: 8 N\n";  // signals start on line 3
    const BadCase cases[] = {
        {" SG_ BVEL_Vx : 70|16@1- (0.001,0) [-1|1] \"\" RIG\n", 3,
         "SG_ BVEL_Vx: start bit 70 + length 16 exceeds 8 bytes"},
        {" SG_ Mo : 3|64@0+ (1,0) [0|0] \"\" RIG\n", 3,
         "SG_ Mo: Motorola start bit 3 (its most significant bit) + length 64 exceeds 8 bytes"},
        {" SG_ Z : 0|0@1+ (1,0) [0|0] \"\" RIG\n", 3, "SG_ Z: length 0"},
        {" SG_ Z : 0|65@1+ (1,0) [0|0] \"\" RIG\n", 3, "SG_ Z length: 65 is outside 0..64"},
        {" SG_ Z : 0|8@2+ (1,0) [0|0] \"\" RIG\n", 3, "byte order must be @1"},
        {" SG_ Z : 0|8@1* (1,0) [0|0] \"\" RIG\n", 3, "sign must be + or -"},
        {" SG_ Z : 0|8@1+ (0,0) [0|0] \"\" RIG\n", 3, "SG_ Z: factor 0"},
        {" SG_ Z : 0|8@1+ (1,0) [5|3] \"\" RIG\n", 3, "SG_ Z: minimum 5 > maximum 3"},
        {" SG_ Z : 0|8@1+ (1,0) [300|400] \"\" RIG\n", 3,
         "range [300|400] holds no raw value of the unsigned 8-bit signal"},
        {" SG_ Z : 0|8@1+ (1,nan) [0|0] \"\" RIG\n", 3, "SG_ Z offset: expected a number"},
        {" SG_ Z : 0|8@1+ (1,1e999) [0|0] \"\" RIG\n", 3, "is not a finite number"},
        {" SG_ A : 0|8@1+ (1,0) [0|0] \"\" RIG\n SG_ B : 4|8@1+ (1,0) [0|0] \"\" RIG\n", 4,
         "SG_ B overlaps SG_ A at bit 4"},
        {" SG_ A : 0|8@1+ (1,0) [0|0] \"\" RIG\n SG_ A : 8|8@1+ (1,0) [0|0] \"\" RIG\n", 4,
         "already has this signal (line 3)"},
        {" SG_ A : 0|8@1+ (1,0) [0|0] \"unit\n\n", 3, "SG_ A unit: string not terminated"},
        {"BO_ 256 M2: 8 N\n", 3, "BO_ M2: id 256 is already BO_ M (line 2)"},
        {"BO_ 4096 M2: 8 N\n", 3, "id 4096 is not an 11-bit identifier"},
        {"BO_ 257 M2: 65 N\n", 3, "BO_ M2 DLC: 65 is outside 0..64"},
        {"\nFOO_ 1;\n", 4, "unknown keyword 'FOO_'"},
        {"\n\n\xff\n", 5, "expected a keyword, found byte 0xFF"},
        {"CM_ SG_ 256 Nope \"x\";\n", 3, "CM_ SG_: BO_ M has no signal Nope"},
        {"CM_ BO_ 999 \"x\";\n", 3, "CM_ BO_: no BO_ with id 999 precedes it"},
        {"VAL_ 256 Nope 1 \"a\" ;\n", 3, "VAL_: BO_ M has no signal Nope"},
        {"BA_ \"GenMsgCycleTime\" BO_ 256 10;\n", 3, "BA_ GenMsgCycleTime: no BA_DEF_ defines it"},
        {"BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\nBA_ \"GenMsgCycleTime\" BO_ 256 20000;\n",
         4, "BA_ GenMsgCycleTime: 20000 is outside [0, 10000]"},
        {"BA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\nBA_ \"GenMsgCycleTime\" BO_ 256 1.5;\n", 4,
         "1.5 is not an integer"},
        {"BA_DEF_ SG_ \"GenSigSNA\" INT 0 0;\nBA_ \"GenSigSNA\" BO_ 256 1;\n", 4,
         "BA_ GenSigSNA: defined for SG_ (line 3), given for BO_"},
        {" SG_ A : 0|8@1+ (1,0) [0|0] \"\" RIG\nBA_DEF_ SG_ \"GenSigSNA\" INT 0 0;\n"
         "BA_ \"GenSigSNA\" SG_ 256 A 256;\n",
         5, "BA_ GenSigSNA: 256 does not fit the 8 bits of SG_ A"},
        {"BA_DEF_ BO_ \"X\" ENUM \"a\",\"b\";\nBA_DEF_DEF_ \"X\" \"c\";\n", 4,
         "BA_DEF_DEF_ X: \"c\" is not one of its values"},
        {"BA_DEF_DEF_ \"Y\" 1;\n", 3, "BA_DEF_DEF_ Y: no BA_DEF_ defines it"},
        {"SIG_VALTYPE_ 256 A : 1;\n", 3, "SIG_VALTYPE_ (IEEE float signals) is not supported"},
        {"BO_TX_BU_ 256 : A\n", 3, "BO_TX_BU_: no ';' ends the statement"},
        {"CM_ \"x\"\n", 4, "CM_: expected ';'"},
    };
    for (const BadCase& c : cases) {
        const std::string text = bo + c.text;
        EXPECT_FILE_ERROR(ParseDbc(text, "bad.dbc"), "bad.dbc", c.line);
        try {
            ParseDbc(text, "bad.dbc");
        } catch (const common::FileError& e) {
            EXPECT_NE(e.detail().find(c.detail), std::string::npos)
                << "got: " << e.what() << "\nwanted: " << c.detail;
        }
    }
    // An SG_ outside a BO_.
    EXPECT_FILE_ERROR(ParseDbc("BU_: A\n SG_ A : 0|8@1+ (1,0) [0|0] \"\" RIG\n", "x.dbc"), "x.dbc",
                      2);
}

TEST(Dbc, ReadDbcNamesAMissingFile) {
    EXPECT_FILE_ERROR(ReadDbc("/nonexistent/go1.dbc"), "/nonexistent/go1.dbc", 0);
}

TEST(Dbc, FuzzedGo1DbcNeverCrashesAndErrorsNameTheFile) {
    const std::string seed(Go1DbcText());
    const std::string tail = seed.substr(seed.find("BA_DEF_ "));
    const test::FuzzCounts counts =
        test::FuzzReader("fuzz.dbc", {{seed, 2500}, {tail, 600}}, 1500, 11,
                         std::string_view("0123456789 \n-.e+|@:;,\"()[]_MmSGBOAV\0\xff", 37),
                         [](const std::string& bytes) { ParseDbc(bytes, "fuzz.dbc"); });
    EXPECT_EQ(counts.accepted + counts.rejected, 3000u);
    EXPECT_GT(counts.rejected, 100u);
    EXPECT_GT(counts.accepted, 100u);  // many edits (in comments, values) stay valid
}

}  // namespace BIMSLAM_UNITY_ID
}  // namespace
}  // namespace bimslam::can
