// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Packing and unpacking DBC signals, precomputed per signal so that the hot path does no string
// lookups, no allocation and no exceptions (DESIGN.md, "Hot path").
//
// A SignalCodec is built once from a DbcSignal (dbc.hpp) and holds everything needed to move a
// value in and out of frame bytes: Intel or Motorola layout (Vector's bit numbering, see dbc.hpp),
// any length 1..64, unsigned or two's complement, factor and offset, the [min|max] range in raw
// units, and the "signal not available" (SNA) pattern:
// - GenSigSNA when the DBC gives it (its raw bit pattern);
// - otherwise the rule of specs/go1-can.md: signed fields the most negative value (0x8000 for 16
//   bits, 0x800000 for 24), unsigned fields all ones — but only when that pattern lies outside
//   the signal's [min|max]. A signal whose range includes it (1-bit flags, the CRC, the 32-bit
//   BridgeTime, reserved fields) or that has no range has no SNA: there the pattern is an
//   ordinary value.
// A MessageCodec is the table of one BO_: its signals' codecs in DBC order, found by name at
// set-up (Index) and used by index afterwards.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/can/dbc.hpp"

namespace bimslam::can {

// What packing a physical value did.
enum class PackResult : uint8_t {
    kOk,         // written, rounded to the nearest raw step
    kClamped,    // outside [min|max] (or the raw type): written as the nearest bound
    kSna,        // not finite: written as the signal's SNA pattern
    kNotFinite,  // not finite and the signal has no SNA: written as raw 0
};

class SignalCodec {
public:
    SignalCodec() = default;
    // Throws common::Error when the layout is impossible (length 0 or > 64, factor 0 or not
    // finite) or when [min|max] holds no raw value of the signal's type.
    explicit SignalCodec(const DbcSignal& signal);

    // ---- Bits ----
    // The signal's raw bit pattern, zero-extended. `data` must hold end_byte() bytes; only bytes
    // first_byte()..end_byte()-1 are read.
    uint64_t Extract(const uint8_t* data) const;
    // Writes the low length() bits of `raw`, leaving every other bit as it was.
    void Insert(uint8_t* data, uint64_t raw) const;
    // The same on the first 8 data bytes loaded as one little-endian word, for signals with
    // fits_word() (all of an 8-byte frame's): a shift and a mask (a byte swap for Motorola).
    uint64_t ExtractWord(uint64_t le_word) const {
        const uint64_t w = order_ == ByteOrder::kIntel ? le_word : __builtin_bswap64(le_word);
        return (w >> word_shift_) & mask_;
    }
    uint64_t InsertWord(uint64_t le_word, uint64_t raw) const {
        if (order_ == ByteOrder::kIntel) {
            return (le_word & ~(mask_ << word_shift_)) | ((raw & mask_) << word_shift_);
        }
        const uint64_t w = __builtin_bswap64(le_word);
        return __builtin_bswap64((w & ~(mask_ << word_shift_)) | ((raw & mask_) << word_shift_));
    }

    // ---- Values ----
    // The raw value as a signed integer (sign-extended when is_signed(); unsigned 64-bit patterns
    // above INT64_MAX wrap, use ToPhysical for those).
    int64_t SignedRaw(uint64_t raw) const {
        if (!signed_ || length_ == 64) return static_cast<int64_t>(raw);
        const unsigned shift = 64 - length_;
        return static_cast<int64_t>(raw << shift) >> shift;
    }
    double ToPhysical(uint64_t raw) const {
        const double r = signed_ ? static_cast<double>(SignedRaw(raw)) : static_cast<double>(raw);
        return r * factor_ + offset_;
    }
    bool IsSna(uint64_t raw) const { return has_sna_ && raw == sna_; }
    // Within [min|max] (always true without a range).
    bool InRange(uint64_t raw) const;
    // physical -> raw: rounded to the nearest step, clamped to [min|max] and to the raw type,
    // SNA for NaN and infinities.
    PackResult ToRaw(double physical, uint64_t* raw) const;

    // Convenience: ToRaw + Insert, Extract + ToPhysical.
    PackResult Pack(uint8_t* data, double physical) const {
        uint64_t raw = 0;
        const PackResult r = ToRaw(physical, &raw);
        Insert(data, raw);
        return r;
    }
    double Unpack(const uint8_t* data) const { return ToPhysical(Extract(data)); }

    // ---- Layout ----
    uint32_t start_bit() const { return start_bit_; }
    uint32_t length() const { return length_; }
    ByteOrder byte_order() const { return order_; }
    bool is_signed() const { return signed_; }
    double factor() const { return factor_; }
    double offset() const { return offset_; }
    bool has_range() const { return has_range_; }
    // The raw range (DBC range intersected with the type's), as physical values.
    double min_physical() const;
    double max_physical() const;
    bool has_sna() const { return has_sna_; }
    uint64_t sna_raw() const { return sna_; }
    uint64_t mask() const { return mask_; }
    uint32_t first_byte() const { return first_byte_; }
    uint32_t end_byte() const { return end_byte_; }  // one past the last byte touched
    bool fits_word() const { return fits_word_; }

private:
    uint32_t start_bit_ = 0;
    uint32_t length_ = 1;
    ByteOrder order_ = ByteOrder::kIntel;
    bool signed_ = false;
    bool has_range_ = false;
    bool has_sna_ = false;
    bool fits_word_ = false;
    uint32_t first_byte_ = 0;
    uint32_t end_byte_ = 1;
    uint32_t word_shift_ = 0;  // LSB position in the little-endian (Intel) or swapped word
    uint64_t mask_ = 1;
    uint64_t sna_ = 0;
    double factor_ = 1.0;
    double offset_ = 0.0;
    int64_t slo_ = 0, shi_ = 0;   // inclusive raw bounds of a signed signal
    uint64_t ulo_ = 0, uhi_ = 0;  // inclusive raw bounds of an unsigned signal
};

// The precomputed table of one message: built at set-up, used by index on the hot path.
class MessageCodec {
public:
    explicit MessageCodec(const DbcMessage& message);

    uint32_t id() const { return id_; }
    bool extended() const { return extended_; }
    uint32_t dlc() const { return dlc_; }
    const std::string& name() const { return name_; }
    int64_t cycle_time_ms() const { return cycle_time_ms_; }
    int64_t timeout_ms() const { return timeout_ms_; }
    size_t size() const { return signals_.size(); }
    const SignalCodec& operator[](size_t i) const { return signals_[i]; }
    std::span<const SignalCodec> signals() const { return signals_; }
    const std::string& signal_name(size_t i) const { return names_[i]; }
    // Index of the signal named `name`; set-up only. Throws common::Error naming the message and
    // the signal when it is absent.
    size_t Index(std::string_view signal_name) const;

private:
    uint32_t id_;
    bool extended_;
    uint32_t dlc_;
    std::string name_;
    int64_t cycle_time_ms_;
    int64_t timeout_ms_;
    std::vector<SignalCodec> signals_;
    std::vector<std::string> names_;
};

}  // namespace bimslam::can
