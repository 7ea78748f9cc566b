// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/dbc.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "drivers/can/signal_codec.hpp"

namespace bimslam::can {
namespace {

using common::FileError;
using common::StatusCode;

// Statements of the format that our file does not use: checked for their terminating ';' only.
constexpr std::string_view kSkippedKeywords[] = {
    "BO_TX_BU_",   "SIG_GROUP_",     "EV_",         "ENVVAR_DATA_",  "SGTYPE_",
    "SGTYPE_VAL_", "BA_DEF_SGTYPE_", "BA_SGTYPE_",  "SIG_TYPE_REF_", "CAT_DEF_",
    "CAT_",        "FILTER",         "BA_DEF_REL_", "BA_REL_",       "BA_DEF_DEF_REL_",
    "BU_SG_REL_",  "BU_EV_REL_",     "BU_BO_REL_",  "SG_MUL_VAL_",   "SIGTYPE_VALTYPE_",
    "EV_DATA_",    "NS_DESC_"};

// The pseudo message CANdb++ keeps signals that belong to no message in: ignored, with every
// statement that refers to it.
constexpr std::string_view kIndependentSignals = "VECTOR__INDEPENDENT_SIG_MSG";

std::string_view ObjectKeyword(DbcObjectType t) {
    switch (t) {
        case DbcObjectType::kNetwork:
            return "network";
        case DbcObjectType::kNode:
            return "BU_";
        case DbcObjectType::kMessage:
            return "BO_";
        case DbcObjectType::kSignal:
            return "SG_";
        case DbcObjectType::kEnvironmentVariable:
            return "EV_";
    }
    return "?";
}

std::string FormatNumber(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

// A BA_ or BA_DEF_DEF_ value as written: a string literal or a number.
struct AttrValue {
    bool is_string = false;
    std::string text;  // the string, or the number's text
    double number = 0.0;
};

// A BA_ waiting for the end of the file, where definitions and defaults are known.
struct PendingAttribute {
    std::string name;
    DbcObjectType object = DbcObjectType::kNetwork;
    size_t message = 0;  // index into Dbc::messages (BO_, SG_)
    size_t signal = 0;   // index into its signals (SG_)
    AttrValue value;
    size_t line = 0;
};

struct PendingDefault {
    std::string name;
    AttrValue value;
    size_t line = 0;
};

bool IsIdentStart(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool IsIdentChar(char c) { return IsIdentStart(c) || (c >= '0' && c <= '9'); }
bool IsDigit(char c) { return c >= '0' && c <= '9'; }

class Parser {
public:
    Parser(std::string_view text, const std::string& file) : text_(text), file_(file) {}

    Dbc Run() {
        while (true) {
            SkipSpace();
            if (AtEnd()) break;
            const size_t line = line_;
            const std::string keyword(Ident("a keyword"));
            if (keyword != "SG_" && keyword != "BO_") current_ = kNone;
            Statement(keyword, line);
        }
        ResolveAttributes();
        CheckSignals();
        return std::move(dbc_);
    }

private:
    static constexpr size_t kNone = static_cast<size_t>(-1);

    // ---- Errors ----
    [[noreturn]] void FailAt(size_t line, const std::string& what) const {
        throw FileError(StatusCode::kParseError, file_, line, what);
    }
    [[noreturn]] void Fail(const std::string& what) const { FailAt(line_, what); }

    // ---- Lexing ----
    bool AtEnd() const { return pos_ >= text_.size(); }
    char Peek() const { return AtEnd() ? '\0' : text_[pos_]; }

    void SkipSpace() {
        while (!AtEnd()) {
            const char c = text_[pos_];
            if (c == '\n') {
                ++line_;
            } else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
                break;
            }
            ++pos_;
        }
    }
    // Spaces within a line only.
    void SkipInlineSpace() {
        while (!AtEnd() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r')) {
            ++pos_;
        }
    }
    bool AtLineEnd() {
        SkipInlineSpace();
        return AtEnd() || text_[pos_] == '\n';
    }
    void SkipRestOfLine() {
        while (!AtEnd() && text_[pos_] != '\n') ++pos_;
    }

    std::string Describe() const {
        if (AtEnd()) return "the end of the file";
        const char c = text_[pos_];
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F) {
            char buf[16];
            std::snprintf(buf, sizeof(buf), "byte 0x%02X", static_cast<unsigned char>(c));
            return buf;
        }
        size_t end = pos_;
        while (end < text_.size() && end - pos_ < 20 && text_[end] != '\n' && text_[end] != ' ') {
            ++end;
        }
        return "'" + std::string(text_.substr(pos_, std::max<size_t>(end - pos_, 1))) + "'";
    }

    std::string_view Ident(std::string_view what) {
        SkipSpace();
        if (AtEnd() || !IsIdentStart(text_[pos_])) {
            Fail("expected " + std::string(what) + ", found " + Describe());
        }
        const size_t start = pos_;
        while (!AtEnd() && IsIdentChar(text_[pos_])) ++pos_;
        return text_.substr(start, pos_ - start);
    }

    void Expect(char c, const std::string& context) {
        SkipSpace();
        if (Peek() != c) Fail(context + ": expected '" + c + "', found " + Describe());
        ++pos_;
    }
    bool Accept(char c) {
        SkipSpace();
        if (Peek() != c) return false;
        ++pos_;
        return true;
    }

    // The text of a decimal number: [+-]digits[.digits][(e|E)[+-]digits], or .digits.
    std::string_view NumberText(const std::string& what) {
        SkipSpace();
        const size_t start = pos_;
        if (Peek() == '+' || Peek() == '-') ++pos_;
        size_t digits = 0;
        while (IsDigit(Peek())) ++pos_, ++digits;
        if (Peek() == '.') {
            ++pos_;
            while (IsDigit(Peek())) ++pos_, ++digits;
        }
        if (digits > 0 && (Peek() == 'e' || Peek() == 'E')) {
            ++pos_;
            if (Peek() == '+' || Peek() == '-') ++pos_;
            size_t exp_digits = 0;
            while (IsDigit(Peek())) ++pos_, ++exp_digits;
            if (exp_digits == 0) digits = 0;
        }
        if (digits == 0) {
            pos_ = start;
            Fail(what + ": expected a number, found " + Describe());
        }
        return text_.substr(start, pos_ - start);
    }

    double Number(const std::string& what) {
        std::string_view t = NumberText(what);
        if (t.front() == '+') t.remove_prefix(1);
        double v = 0.0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v)) {
            Fail(what + ": '" + std::string(t) + "' is not a finite number");
        }
        return v;
    }

    int64_t Integer(const std::string& what) {
        std::string_view t = NumberText(what);
        if (t.front() == '+') t.remove_prefix(1);
        int64_t v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size()) {
            Fail(what + ": '" + std::string(t) + "' is not an integer in the 64-bit range");
        }
        return v;
    }

    uint64_t Unsigned(const std::string& what, uint64_t max) {
        const int64_t v = Integer(what);
        if (v < 0 || static_cast<uint64_t>(v) > max) {
            Fail(what + ": " + std::to_string(v) + " is outside 0.." + std::to_string(max));
        }
        return static_cast<uint64_t>(v);
    }

    // "..." with \" and \\ escapes; may span lines.
    std::string String(const std::string& what) {
        SkipSpace();
        if (Peek() != '"') Fail(what + ": expected a string in \"\", found " + Describe());
        const size_t open_line = line_;
        ++pos_;
        std::string out;
        while (true) {
            if (AtEnd()) FailAt(open_line, what + ": string not terminated");
            const char c = text_[pos_++];
            if (c == '"') break;
            if (c == '\n') ++line_;
            if (c == '\\' && !AtEnd() && (text_[pos_] == '"' || text_[pos_] == '\\')) {
                out += text_[pos_++];
                continue;
            }
            out += c;
        }
        return out;
    }

    AttrValue Value(const std::string& what) {
        SkipSpace();
        AttrValue v;
        if (Peek() == '"') {
            v.is_string = true;
            v.text = String(what);
        } else {
            v.text = std::string(NumberText(what));
            std::string_view t = v.text;
            if (t.front() == '+') t.remove_prefix(1);
            const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v.number);
            if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v.number)) {
                Fail(what + ": '" + v.text + "' is not a finite number");
            }
        }
        return v;
    }

    // Skips to the ';' ending the statement (strings may hold ';').
    void SkipStatement(const std::string& keyword, size_t line) {
        while (true) {
            SkipSpace();
            if (AtEnd()) FailAt(line, keyword + ": no ';' ends the statement");
            if (Peek() == '"') {
                String(keyword);
            } else if (text_[pos_++] == ';') {
                return;
            }
        }
    }

    // ---- Message references ----
    // A message id as the DBC writes it: 11-bit, or 29-bit with bit 31 set.
    struct RawId {
        uint32_t id = 0;
        bool extended = false;
        bool pseudo = false;  // bits 29..30 set: only VECTOR__INDEPENDENT_SIG_MSG may be this
    };
    RawId MessageId(const std::string& what) {
        const uint64_t v = Unsigned(what + " id", 0xFFFFFFFFull);
        RawId r;
        if (v & 0x80000000ull) {
            r.extended = true;
            r.id = static_cast<uint32_t>(v & 0x7FFFFFFFull);
            r.pseudo = r.id > 0x1FFFFFFF;
        } else if (v > 0x7FF) {
            Fail(what + ": id " + std::to_string(v) +
                 " is not an 11-bit identifier (extended identifiers have bit 31 set)");
        } else {
            r.id = static_cast<uint32_t>(v);
        }
        return r;
    }

    // Index of a message referred to by CM_, BA_ or VAL_; kNone for the ignored pseudo message.
    size_t FindMessage(const RawId& r, const std::string& what, size_t line) const {
        if (r.pseudo) return kNone;
        for (size_t i = 0; i < dbc_.messages.size(); ++i) {
            if (dbc_.messages[i].id == r.id && dbc_.messages[i].extended == r.extended) return i;
        }
        FailAt(line, what + ": no BO_ with id " + std::to_string(r.id) +
                         (r.extended ? " (extended)" : "") + " precedes it");
    }
    size_t FindSignal(size_t message, std::string_view name, const std::string& what,
                      size_t line) const {
        const auto& sigs = dbc_.messages[message].signals;
        for (size_t i = 0; i < sigs.size(); ++i) {
            if (sigs[i].name == name) return i;
        }
        FailAt(line, what + ": BO_ " + dbc_.messages[message].name + " has no signal " +
                         std::string(name));
    }

    // ---- Statements ----
    void Statement(const std::string& keyword, size_t line) {
        if (keyword == "VERSION") {
            dbc_.version = String("VERSION");
        } else if (keyword == "NS_") {
            // "NS_ :" then the new-symbol list, one indented name per line.
            Expect(':', "NS_");
            SkipRestOfLine();
            while (!AtEnd()) {
                ++pos_;  // the '\n'
                ++line_;
                if (AtEnd() || (text_[pos_] != ' ' && text_[pos_] != '\t' && text_[pos_] != '\r' &&
                                text_[pos_] != '\n')) {
                    break;
                }
                SkipRestOfLine();
            }
        } else if (keyword == "BS_") {
            Expect(':', "BS_");
            SkipRestOfLine();  // baud rate and BTR registers: obsolete
        } else if (keyword == "BU_") {
            Expect(':', "BU_");
            while (!AtLineEnd()) dbc_.nodes.emplace_back(Ident("a node name (BU_)"));
        } else if (keyword == "VAL_TABLE_") {
            std::string name(Ident("a value table name (VAL_TABLE_)"));
            for (const auto& t : dbc_.value_tables) {
                if (t.first == name) Fail("VAL_TABLE_ " + name + " is defined twice");
            }
            DbcValueTable table = ValueDescriptions("VAL_TABLE_ " + name);
            dbc_.value_tables.emplace_back(std::move(name), std::move(table));
        } else if (keyword == "BO_") {
            Message(line);
        } else if (keyword == "SG_") {
            Signal(line);
        } else if (keyword == "CM_") {
            Comment(line);
        } else if (keyword == "BA_DEF_") {
            AttributeDefinition(line);
        } else if (keyword == "BA_DEF_DEF_") {
            PendingDefault d;
            d.line = line;
            d.name = String("BA_DEF_DEF_ name");
            d.value = Value("BA_DEF_DEF_ " + d.name);
            Expect(';', "BA_DEF_DEF_ " + d.name);
            defaults_.push_back(std::move(d));
        } else if (keyword == "BA_") {
            Attribute(line);
        } else if (keyword == "VAL_") {
            SignalValues(line);
        } else if (keyword == "SIG_VALTYPE_") {
            Fail("SIG_VALTYPE_ (IEEE float signals) is not supported");
        } else if (std::find(std::begin(kSkippedKeywords), std::end(kSkippedKeywords), keyword) !=
                   std::end(kSkippedKeywords)) {
            SkipStatement(keyword, line);
        } else {
            FailAt(line, "unknown keyword '" + keyword + "'");
        }
    }

    // (integer "text")* ;
    DbcValueTable ValueDescriptions(const std::string& what) {
        DbcValueTable table;
        while (!Accept(';')) {
            const int64_t v = Integer(what + " value");
            table.emplace_back(v, String(what + " description of " + std::to_string(v)));
        }
        return table;
    }

    // BO_ <id> <name>: <dlc> <transmitter>
    void Message(size_t line) {
        const RawId r = MessageId("BO_");
        const std::string name(Ident("a message name (BO_)"));
        const std::string what = "BO_ " + name;
        Expect(':', what);
        const uint32_t dlc = static_cast<uint32_t>(Unsigned(what + " DLC", 64));
        std::string transmitter;
        if (!AtLineEnd()) transmitter = Ident("a transmitter node (BO_)");
        if (!AtLineEnd()) Fail(what + ": unexpected " + Describe() + " after the transmitter");
        if (r.pseudo) {
            if (name != kIndependentSignals) {
                FailAt(line, what + ": extended id " + std::to_string(r.id) + " exceeds 29 bits");
            }
            current_ = kNone;
            skipping_signals_ = true;
            return;
        }
        for (const auto& m : dbc_.messages) {
            if (m.id == r.id && m.extended == r.extended) {
                FailAt(line, what + ": id " + std::to_string(r.id) + " is already BO_ " + m.name +
                                 " (line " + std::to_string(m.line) + ")");
            }
            if (m.name == name) {
                FailAt(line, what + ": the name is already used by the BO_ on line " +
                                 std::to_string(m.line));
            }
        }
        DbcMessage m;
        m.id = r.id;
        m.extended = r.extended;
        m.name = name;
        m.dlc = dlc;
        m.transmitter = std::move(transmitter);
        m.line = line;
        dbc_.messages.push_back(std::move(m));
        current_ = dbc_.messages.size() - 1;
        skipping_signals_ = false;
    }

    // SG_ <name> [M|m<k>] : <start>|<length>@<0|1><+|-> (<factor>,<offset>) [<min>|<max>]
    //     "<unit>" <receiver>[,<receiver>...]
    void Signal(size_t line) {
        DbcSignal s;
        s.line = line;
        s.name = Ident("a signal name (SG_)");
        const std::string what = "SG_ " + s.name;
        SkipSpace();
        if (Peek() != ':') {
            s.multiplexer = Ident("a multiplexer indicator or ':'");
            const bool ok =
                s.multiplexer == "M" ||
                (s.multiplexer.size() >= 2 && s.multiplexer[0] == 'm' && IsDigit(s.multiplexer[1]));
            if (!ok) Fail(what + ": '" + s.multiplexer + "' is not a multiplexer indicator");
        }
        Expect(':', what);
        s.start_bit = static_cast<uint32_t>(Unsigned(what + " start bit", 511));
        Expect('|', what + " after the start bit");
        s.length = static_cast<uint32_t>(Unsigned(what + " length", 64));
        if (s.length == 0) Fail(what + ": length 0 (must be 1..64)");
        Expect('@', what + " after the length");
        if (Peek() == '0' || Peek() == '1') {
            s.byte_order = text_[pos_++] == '1' ? ByteOrder::kIntel : ByteOrder::kMotorola;
        } else {
            Fail(what + ": byte order must be @1 (Intel) or @0 (Motorola), found " + Describe());
        }
        if (Peek() == '+' || Peek() == '-') {
            s.is_signed = text_[pos_++] == '-';
        } else {
            Fail(what + ": sign must be + or -, found " + Describe());
        }
        Expect('(', what + " before the factor");
        s.factor = Number(what + " factor");
        Expect(',', what + " after the factor");
        s.offset = Number(what + " offset");
        Expect(')', what + " after the offset");
        Expect('[', what + " before the minimum");
        s.minimum = Number(what + " minimum");
        Expect('|', what + " after the minimum");
        s.maximum = Number(what + " maximum");
        Expect(']', what + " after the maximum");
        s.unit = String(what + " unit");
        while (!AtLineEnd()) {
            s.receivers.emplace_back(Ident("a receiver node (SG_)"));
            SkipInlineSpace();
            if (Peek() == ',') ++pos_;
        }
        if (s.factor == 0.0) FailAt(line, what + ": factor 0");
        if (s.minimum > s.maximum) {
            FailAt(line, what + ": minimum " + FormatNumber(s.minimum) + " > maximum " +
                             FormatNumber(s.maximum));
        }
        if (skipping_signals_) return;
        if (current_ == kNone) FailAt(line, what + " does not follow a BO_");
        DbcMessage& m = dbc_.messages[current_];
        CheckLayout(s, m.dlc);
        for (const auto& other : m.signals) {
            if (other.name == s.name) {
                FailAt(line, what + ": BO_ " + m.name + " already has this signal (line " +
                                 std::to_string(other.line) + ")");
            }
        }
        m.signals.push_back(std::move(s));
    }

    void CheckLayout(const DbcSignal& s, uint32_t dlc) const {
        const uint64_t bits = uint64_t{dlc} * 8;
        if (s.byte_order == ByteOrder::kIntel) {
            if (s.start_bit + uint64_t{s.length} > bits) {
                FailAt(s.line, "SG_ " + s.name + ": start bit " + std::to_string(s.start_bit) +
                                   " + length " + std::to_string(s.length) + " exceeds " +
                                   std::to_string(dlc) + " bytes");
            }
        } else {
            // Position in the sequential big-endian order (byte 0 bit 7 first).
            const uint64_t msb = (s.start_bit / 8) * 8 + (7 - s.start_bit % 8);
            if (s.start_bit >= bits || msb + s.length > bits) {
                FailAt(s.line, "SG_ " + s.name + ": Motorola start bit " +
                                   std::to_string(s.start_bit) + " (its most significant bit)" +
                                   " + length " + std::to_string(s.length) + " exceeds " +
                                   std::to_string(dlc) + " bytes");
            }
        }
    }

    // CM_ "text"; | CM_ BU_ <node> "text"; | CM_ BO_ <id> "text"; | CM_ SG_ <id> <sig> "text";
    // | CM_ EV_ <var> "text";
    void Comment(size_t line) {
        SkipSpace();
        if (Peek() == '"') {
            dbc_.comment = String("CM_");
            Expect(';', "CM_");
            return;
        }
        const std::string kind(Ident("BU_, BO_, SG_, EV_ or a string after CM_"));
        if (kind == "BU_" || kind == "EV_") {
            Ident("a name after CM_ " + kind);
            String("CM_ " + kind);  // node and variable comments are not kept
        } else if (kind == "BO_") {
            const RawId r = MessageId("CM_ BO_");
            std::string text = String("CM_ BO_");
            const size_t m = FindMessage(r, "CM_ BO_", line);
            if (m != kNone) dbc_.messages[m].comment = std::move(text);
        } else if (kind == "SG_") {
            const RawId r = MessageId("CM_ SG_");
            const std::string sig(Ident("a signal name after CM_ SG_"));
            std::string text = String("CM_ SG_ " + sig);
            const size_t m = FindMessage(r, "CM_ SG_ " + sig, line);
            if (m != kNone) {
                dbc_.messages[m].signals[FindSignal(m, sig, "CM_ SG_", line)].comment =
                    std::move(text);
            }
        } else {
            FailAt(line, "CM_ " + kind + ": expected BU_, BO_, SG_ or EV_");
        }
        Expect(';', "CM_ " + kind);
    }

    // BA_DEF_ [BU_|BO_|SG_|EV_] "<name>" INT|HEX <min> <max> | FLOAT <min> <max> | STRING
    // | ENUM "<a>","<b>"... ;
    void AttributeDefinition(size_t line) {
        DbcAttributeDefinition d;
        d.line = line;
        SkipSpace();
        if (Peek() != '"') {
            const std::string kind(Ident("BU_, BO_, SG_, EV_ or a name after BA_DEF_"));
            if (kind == "BU_") {
                d.object = DbcObjectType::kNode;
            } else if (kind == "BO_") {
                d.object = DbcObjectType::kMessage;
            } else if (kind == "SG_") {
                d.object = DbcObjectType::kSignal;
            } else if (kind == "EV_") {
                d.object = DbcObjectType::kEnvironmentVariable;
            } else {
                FailAt(line, "BA_DEF_ " + kind + ": expected BU_, BO_, SG_ or EV_");
            }
        }
        d.name = String("BA_DEF_ name");
        const std::string what = "BA_DEF_ " + d.name;
        const std::string type(Ident("an attribute type (INT, HEX, FLOAT, STRING, ENUM)"));
        if (type == "INT" || type == "HEX") {
            d.type = type == "INT" ? DbcValueType::kInt : DbcValueType::kHex;
            d.minimum = static_cast<double>(Integer(what + " minimum"));
            d.maximum = static_cast<double>(Integer(what + " maximum"));
        } else if (type == "FLOAT") {
            d.type = DbcValueType::kFloat;
            d.minimum = Number(what + " minimum");
            d.maximum = Number(what + " maximum");
        } else if (type == "STRING") {
            d.type = DbcValueType::kString;
        } else if (type == "ENUM") {
            d.type = DbcValueType::kEnum;
            SkipSpace();
            while (Peek() == '"') {
                d.enum_values.push_back(String(what + " enum value"));
                if (!Accept(',')) break;
                SkipSpace();
            }
        } else {
            FailAt(line, what + ": unknown type '" + type + "'");
        }
        if (d.minimum > d.maximum) FailAt(line, what + ": minimum > maximum");
        Expect(';', what);
        for (const auto& other : dbc_.attributes) {
            if (other.name == d.name) {
                FailAt(line, what + " is already defined on line " + std::to_string(other.line));
            }
        }
        dbc_.attributes.push_back(std::move(d));
    }

    // BA_ "<name>" [BU_ <node> | BO_ <id> | SG_ <id> <signal> | EV_ <var>] <value> ;
    void Attribute(size_t line) {
        PendingAttribute a;
        a.line = line;
        a.name = String("BA_ name");
        const std::string what = "BA_ " + a.name;
        SkipSpace();
        bool ignored = false;
        if (IsIdentStart(Peek())) {
            const std::string kind(Ident("BU_, BO_, SG_ or EV_"));
            if (kind == "BU_" || kind == "EV_") {
                a.object =
                    kind == "BU_" ? DbcObjectType::kNode : DbcObjectType::kEnvironmentVariable;
                Ident("a name after " + what + " " + kind);
            } else if (kind == "BO_" || kind == "SG_") {
                a.object = kind == "BO_" ? DbcObjectType::kMessage : DbcObjectType::kSignal;
                const RawId r = MessageId(what + " " + kind);
                std::string sig;
                if (kind == "SG_") sig = Ident("a signal name");
                a.message = FindMessage(r, what, line);
                ignored = a.message == kNone;
                if (!ignored && kind == "SG_") a.signal = FindSignal(a.message, sig, what, line);
            } else {
                FailAt(line, what + ": expected BU_, BO_, SG_ or EV_, found " + kind);
            }
        }
        a.value = Value(what);
        Expect(';', what);
        if (!ignored) attributes_.push_back(std::move(a));
    }

    // VAL_ <id> <signal> (<value> "<text>")* ;   (VAL_ <env var> ... ; is skipped)
    void SignalValues(size_t line) {
        SkipSpace();
        if (!IsDigit(Peek())) {
            SkipStatement("VAL_", line);  // value descriptions of an environment variable
            return;
        }
        const RawId r = MessageId("VAL_");
        const std::string sig(Ident("a signal name after VAL_"));
        DbcValueTable table = ValueDescriptions("VAL_ " + sig);
        const size_t m = FindMessage(r, "VAL_ " + sig, line);
        if (m == kNone) return;
        DbcSignal& s = dbc_.messages[m].signals[FindSignal(m, sig, "VAL_", line)];
        if (!s.values.empty()) FailAt(line, "VAL_ " + sig + ": value descriptions given twice");
        s.values = std::move(table);
    }

    // ---- After the last line ----
    const DbcAttributeDefinition* Definition(const std::string& name) const {
        for (const auto& d : dbc_.attributes) {
            if (d.name == name) return &d;
        }
        return nullptr;
    }

    // Checks a value against its definition.
    void CheckValue(const DbcAttributeDefinition& d, const AttrValue& v, const std::string& what,
                    size_t line) const {
        const bool limited = d.minimum != 0.0 || d.maximum != 0.0;
        switch (d.type) {
            case DbcValueType::kInt:
            case DbcValueType::kHex:
            case DbcValueType::kFloat:
                if (v.is_string) FailAt(line, what + ": \"" + v.text + "\" is not a number");
                if (d.type != DbcValueType::kFloat &&
                    (v.number != std::floor(v.number) || std::fabs(v.number) > 9.0e15)) {
                    FailAt(line, what + ": " + v.text + " is not an integer");
                }
                if (limited && (v.number < d.minimum || v.number > d.maximum)) {
                    FailAt(line, what + ": " + v.text + " is outside [" + FormatNumber(d.minimum) +
                                     ", " + FormatNumber(d.maximum) + "]");
                }
                break;
            case DbcValueType::kString:
                if (!v.is_string) FailAt(line, what + ": " + v.text + " is not a string");
                break;
            case DbcValueType::kEnum:
                if (v.is_string) {
                    if (std::find(d.enum_values.begin(), d.enum_values.end(), v.text) ==
                        d.enum_values.end()) {
                        FailAt(line, what + ": \"" + v.text + "\" is not one of its values");
                    }
                } else if (v.number != std::floor(v.number) || v.number < 0 ||
                           v.number >= static_cast<double>(d.enum_values.size())) {
                    FailAt(line, what + ": " + v.text + " is not an index of its values");
                }
                break;
        }
    }

    static bool FitsBits(uint64_t v, uint32_t bits) { return bits >= 64 || (v >> bits) == 0; }

    void ApplySna(DbcSignal& s, double v, const std::string& what, size_t line) const {
        if (v < 0) FailAt(line, what + ": negative");
        const uint64_t raw = static_cast<uint64_t>(v);
        if (!FitsBits(raw, s.length)) {
            FailAt(line, what + ": " + std::to_string(raw) + " does not fit the " +
                             std::to_string(s.length) + " bits of SG_ " + s.name);
        }
        s.gen_sig_sna = raw;
    }

    void ResolveAttributes() {
        for (const PendingDefault& p : defaults_) {
            auto it = std::find_if(dbc_.attributes.begin(), dbc_.attributes.end(),
                                   [&](const auto& d) { return d.name == p.name; });
            if (it == dbc_.attributes.end()) {
                FailAt(p.line, "BA_DEF_DEF_ " + p.name + ": no BA_DEF_ defines it");
            }
            if (it->default_value) FailAt(p.line, "BA_DEF_DEF_ " + p.name + " is given twice");
            CheckValue(*it, p.value, "BA_DEF_DEF_ " + p.name, p.line);
            it->default_value = p.value.text;
        }
        // Defaults first, explicit values override them.
        auto default_number = [&](const char* name) -> std::optional<double> {
            const DbcAttributeDefinition* d = Definition(name);
            if (!d || !d->default_value || d->type == DbcValueType::kString ||
                d->type == DbcValueType::kEnum) {
                return std::nullopt;
            }
            double v = 0.0;
            const std::string& t = *d->default_value;
            const char* b = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
            std::from_chars(b, t.data() + t.size(), v);
            return v;
        };
        const auto cycle = default_number("GenMsgCycleTime");
        const auto timeout = default_number("GenMsgTimeout");
        const auto sna = default_number("GenSigSNA");
        for (DbcMessage& m : dbc_.messages) {
            if (cycle) m.cycle_time_ms = static_cast<int64_t>(*cycle);
            if (timeout) m.timeout_ms = static_cast<int64_t>(*timeout);
            if (sna && *sna > 0) {
                // A non-zero default applies where it fits; 0, our file's default, means "none"
                // because raw 0 is an ordinary value of nearly every signal.
                for (DbcSignal& s : m.signals) {
                    if (FitsBits(static_cast<uint64_t>(*sna), s.length)) {
                        s.gen_sig_sna = static_cast<uint64_t>(*sna);
                    }
                }
            }
        }
        for (const PendingAttribute& a : attributes_) {
            const std::string what = "BA_ " + a.name;
            const DbcAttributeDefinition* d = Definition(a.name);
            if (!d) FailAt(a.line, what + ": no BA_DEF_ defines it");
            if (d->object != a.object) {
                FailAt(a.line, what + ": defined for " + std::string(ObjectKeyword(d->object)) +
                                   " (line " + std::to_string(d->line) + "), given for " +
                                   std::string(ObjectKeyword(a.object)));
            }
            CheckValue(*d, a.value, what, a.line);
            if (a.object == DbcObjectType::kMessage) {
                DbcMessage& m = dbc_.messages[a.message];
                if (a.name == "GenMsgCycleTime" || a.name == "GenMsgTimeout") {
                    if (a.value.number < 0) FailAt(a.line, what + ": negative");
                    const auto ms = static_cast<int64_t>(a.value.number);
                    (a.name == "GenMsgCycleTime" ? m.cycle_time_ms : m.timeout_ms) = ms;
                }
            } else if (a.object == DbcObjectType::kSignal && a.name == "GenSigSNA") {
                ApplySna(dbc_.messages[a.message].signals[a.signal], a.value.number, what, a.line);
            }
        }
    }

    // Every signal's codec can be built (its range holds raw values) and no two plain signals
    // share a bit.
    void CheckSignals() const {
        for (const DbcMessage& m : dbc_.messages) {
            std::vector<size_t> owner(size_t{m.dlc} * 8, kNone);
            for (size_t i = 0; i < m.signals.size(); ++i) {
                const DbcSignal& s = m.signals[i];
                try {
                    SignalCodec codec(s);
                    (void)codec;
                } catch (const common::Error& e) {
                    FailAt(s.line, e.what());
                }
                if (!s.multiplexer.empty() && s.multiplexer != "M") continue;
                uint32_t bit = s.start_bit;
                for (uint32_t k = 0; k < s.length; ++k) {
                    if (bit >= owner.size()) break;  // CheckLayout ruled this out
                    if (owner[bit] != kNone) {
                        FailAt(s.line, "SG_ " + s.name + " overlaps SG_ " +
                                           m.signals[owner[bit]].name + " at bit " +
                                           std::to_string(bit));
                    }
                    owner[bit] = i;
                    if (s.byte_order == ByteOrder::kIntel) {
                        ++bit;
                    } else {
                        bit = bit % 8 == 0 ? bit + 15 : bit - 1;  // the sawtooth
                    }
                }
            }
        }
    }

    std::string_view text_;
    const std::string& file_;
    size_t pos_ = 0;
    size_t line_ = 1;
    Dbc dbc_;
    size_t current_ = kNone;  // the BO_ that SG_ lines belong to
    bool skipping_signals_ = false;
    std::vector<PendingAttribute> attributes_;
    std::vector<PendingDefault> defaults_;
};

}  // namespace

const DbcSignal* DbcMessage::FindSignal(std::string_view signal_name) const {
    for (const auto& s : signals) {
        if (s.name == signal_name) return &s;
    }
    return nullptr;
}

const DbcMessage* Dbc::FindMessage(uint32_t id, bool is_extended) const {
    for (const auto& m : messages) {
        if (m.id == id && m.extended == is_extended) return &m;
    }
    return nullptr;
}

const DbcMessage* Dbc::FindMessage(std::string_view message_name) const {
    for (const auto& m : messages) {
        if (m.name == message_name) return &m;
    }
    return nullptr;
}

Dbc ParseDbc(std::string_view text, const std::string& file_name) {
    return Parser(text, file_name).Run();
}

Dbc ReadDbc(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        const int err = errno;
        throw FileError(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError, path.string(),
                        0, std::string("cannot open: ") + std::strerror(err));
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw FileError(StatusCode::kIoError, path.string(), 0, "read failed");
    return ParseDbc(buffer.str(), path.string());
}

const Dbc& Go1Dbc() {
    static const Dbc dbc = ParseDbc(Go1DbcText(), "drivers/can/go1_odometry.dbc (embedded)");
    return dbc;
}

}  // namespace bimslam::can
