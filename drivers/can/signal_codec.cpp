// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "drivers/can/signal_codec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "algorithms/common/status.hpp"

namespace bimslam::can {
namespace {

using common::Error;
using common::StatusCode;

std::string Num(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

// double -> integer without undefined behaviour: saturates at the bounds (NaN gives lo).
int64_t SaturateSigned(double d, int64_t lo, int64_t hi) {
    if (!(d > static_cast<double>(lo))) return lo;
    if (d >= static_cast<double>(hi)) return hi;  // double(INT64_MAX) is 2^63: exclusive here
    return std::clamp(static_cast<int64_t>(d), lo, hi);
}
uint64_t SaturateUnsigned(double d, uint64_t lo, uint64_t hi) {
    if (!(d > static_cast<double>(lo))) return lo;
    if (d >= static_cast<double>(hi)) return hi;
    return std::clamp(static_cast<uint64_t>(d), lo, hi);
}

// A DBC bound divided by the factor: the nearest integer when it is one up to rounding noise
// (-32.767 / 0.001 is -32767.000000000004), else rounded inwards.
double SnapLow(double r) {
    const double n = std::round(r);
    return std::fabs(r - n) <= 1e-9 * std::max(1.0, std::fabs(r)) ? n : std::ceil(r);
}
double SnapHigh(double r) {
    const double n = std::round(r);
    return std::fabs(r - n) <= 1e-9 * std::max(1.0, std::fabs(r)) ? n : std::floor(r);
}

}  // namespace

SignalCodec::SignalCodec(const DbcSignal& s) {
    const std::string what = "SG_ " + s.name + ": ";
    if (s.length < 1 || s.length > 64) {
        throw Error(StatusCode::kInvalidArgument,
                    what + "length " + std::to_string(s.length) + " (must be 1..64)");
    }
    if (!std::isfinite(s.factor) || s.factor == 0.0 || !std::isfinite(s.offset)) {
        throw Error(StatusCode::kInvalidArgument,
                    what + "factor " + Num(s.factor) + " / offset " + Num(s.offset) +
                        " (the factor must be finite and not 0, the offset finite)");
    }
    start_bit_ = s.start_bit;
    length_ = s.length;
    order_ = s.byte_order;
    signed_ = s.is_signed;
    factor_ = s.factor;
    offset_ = s.offset;
    mask_ = length_ == 64 ? ~uint64_t{0} : (uint64_t{1} << length_) - 1;

    first_byte_ = start_bit_ / 8;
    if (order_ == ByteOrder::kIntel) {
        end_byte_ = (start_bit_ + length_ - 1) / 8 + 1;
        fits_word_ = start_bit_ + length_ <= 64;
        word_shift_ = fits_word_ ? start_bit_ : 0;
    } else {
        // Sequential big-endian position (0 = byte 0 bit 7) of the MSB and the LSB; in the
        // byte-swapped word, position q is bit 63 - q.
        const uint32_t msb = (start_bit_ / 8) * 8 + 7 - start_bit_ % 8;
        const uint32_t lsb = msb + length_ - 1;
        end_byte_ = lsb / 8 + 1;
        fits_word_ = lsb < 64;
        word_shift_ = fits_word_ ? 63 - lsb : 0;
    }

    // Raw bounds: the type's, narrowed by [min|max].
    const int64_t type_slo =
        length_ == 64 ? std::numeric_limits<int64_t>::min() : -(int64_t{1} << (length_ - 1));
    const int64_t type_shi =
        length_ == 64 ? std::numeric_limits<int64_t>::max() : (int64_t{1} << (length_ - 1)) - 1;
    const uint64_t type_uhi = mask_;
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    has_range_ = s.HasRange();
    if (has_range_) {
        double a = (s.minimum - offset_) / factor_;
        double b = (s.maximum - offset_) / factor_;
        if (factor_ < 0) std::swap(a, b);
        lo = SnapLow(a);
        hi = SnapHigh(b);
    }
    bool empty = lo > hi;
    if (signed_) {
        slo_ = SaturateSigned(lo, type_slo, type_shi);
        shi_ = SaturateSigned(hi, type_slo, type_shi);
        empty = empty || hi < static_cast<double>(type_slo) || lo > static_cast<double>(type_shi);
    } else {
        ulo_ = SaturateUnsigned(lo, 0, type_uhi);
        uhi_ = SaturateUnsigned(hi, 0, type_uhi);
        empty = empty || hi < 0.0 || lo > static_cast<double>(type_uhi);
    }
    if (empty) {
        throw Error(StatusCode::kInvalidArgument,
                    what + "range [" + Num(s.minimum) + "|" + Num(s.maximum) +
                        "] holds no raw value of the " + (signed_ ? "signed " : "unsigned ") +
                        std::to_string(length_) + "-bit signal");
    }

    if (s.gen_sig_sna) {
        has_sna_ = true;
        sna_ = *s.gen_sig_sna & mask_;
    } else if (has_range_) {
        // specs/go1-can.md: signed -> the most negative value, unsigned -> all ones; an SNA only
        // when the range excludes it.
        sna_ = signed_ ? uint64_t{1} << (length_ - 1) : mask_;
        has_sna_ = !InRange(sna_);
    }
}

bool SignalCodec::InRange(uint64_t raw) const {
    if (signed_) {
        const int64_t v = SignedRaw(raw & mask_);
        return v >= slo_ && v <= shi_;
    }
    raw &= mask_;
    return raw >= ulo_ && raw <= uhi_;
}

double SignalCodec::min_physical() const {
    return signed_ ? ToPhysical(static_cast<uint64_t>(factor_ > 0 ? slo_ : shi_) & mask_)
                   : ToPhysical(factor_ > 0 ? ulo_ : uhi_);
}
double SignalCodec::max_physical() const {
    return signed_ ? ToPhysical(static_cast<uint64_t>(factor_ > 0 ? shi_ : slo_) & mask_)
                   : ToPhysical(factor_ > 0 ? uhi_ : ulo_);
}

PackResult SignalCodec::ToRaw(double physical, uint64_t* raw) const {
    if (!std::isfinite(physical)) {
        *raw = has_sna_ ? sna_ : 0;
        return has_sna_ ? PackResult::kSna : PackResult::kNotFinite;
    }
    const double r = std::round((physical - offset_) / factor_);
    if (signed_) {
        const int64_t v = SaturateSigned(r, slo_, shi_);
        *raw = static_cast<uint64_t>(v) & mask_;
        const bool clamped = r < static_cast<double>(slo_) || r > static_cast<double>(shi_);
        return clamped ? PackResult::kClamped : PackResult::kOk;
    }
    *raw = SaturateUnsigned(r, ulo_, uhi_);
    const bool clamped = r < static_cast<double>(ulo_) || r > static_cast<double>(uhi_);
    return clamped ? PackResult::kClamped : PackResult::kOk;
}

uint64_t SignalCodec::Extract(const uint8_t* data) const {
    uint64_t v = 0;
    uint32_t byte = start_bit_ / 8;
    if (order_ == ByteOrder::kIntel) {
        // Ascending from the LSB: the rest of the start byte, then whole bytes upwards.
        uint32_t off = start_bit_ % 8;
        uint32_t got = 0;
        while (got < length_) {
            const uint32_t n = std::min(8 - off, length_ - got);
            const uint64_t chunk = (uint64_t{data[byte]} >> off) & ((1u << n) - 1);
            v |= chunk << got;
            got += n;
            ++byte;
            off = 0;
        }
    } else {
        // Descending from the MSB: bits (start % 8)..0 of the start byte, then bits 7..0 of the
        // following bytes (the sawtooth), the last byte's high bits last.
        uint32_t avail = start_bit_ % 8 + 1;
        uint32_t left = length_;
        while (left > 0) {
            const uint32_t n = std::min(avail, left);
            const uint64_t chunk = (uint64_t{data[byte]} >> (avail - n)) & ((1u << n) - 1);
            v = (v << n) | chunk;
            left -= n;
            ++byte;
            avail = 8;
        }
    }
    return v;
}

void SignalCodec::Insert(uint8_t* data, uint64_t raw) const {
    raw &= mask_;
    uint32_t byte = start_bit_ / 8;
    if (order_ == ByteOrder::kIntel) {
        uint32_t off = start_bit_ % 8;
        uint32_t done = 0;
        while (done < length_) {
            const uint32_t n = std::min(8 - off, length_ - done);
            const uint32_t m = ((1u << n) - 1) << off;
            const uint32_t bits = static_cast<uint32_t>((raw >> done) << off) & m;
            data[byte] = static_cast<uint8_t>((data[byte] & ~m) | bits);
            done += n;
            ++byte;
            off = 0;
        }
    } else {
        uint32_t avail = start_bit_ % 8 + 1;
        uint32_t left = length_;
        while (left > 0) {
            const uint32_t n = std::min(avail, left);
            const uint32_t shift = avail - n;
            const uint32_t m = ((1u << n) - 1) << shift;
            const uint32_t bits = static_cast<uint32_t>((raw >> (left - n)) << shift) & m;
            data[byte] = static_cast<uint8_t>((data[byte] & ~m) | bits);
            left -= n;
            ++byte;
            avail = 8;
        }
    }
}

MessageCodec::MessageCodec(const DbcMessage& m)
    : id_(m.id),
      extended_(m.extended),
      dlc_(m.dlc),
      name_(m.name),
      cycle_time_ms_(m.cycle_time_ms),
      timeout_ms_(m.timeout_ms) {
    signals_.reserve(m.signals.size());
    names_.reserve(m.signals.size());
    for (const DbcSignal& s : m.signals) {
        try {
            signals_.emplace_back(s);
        } catch (const Error& e) {
            throw Error(e.code(), "BO_ " + m.name + ": " + e.what());
        }
        names_.push_back(s.name);
    }
}

size_t MessageCodec::Index(std::string_view signal_name) const {
    for (size_t i = 0; i < names_.size(); ++i) {
        if (names_[i] == signal_name) return i;
    }
    throw Error(StatusCode::kNotFound,
                "BO_ " + name_ + " has no signal " + std::string(signal_name));
}

}  // namespace bimslam::can
