// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/bim/ifc_writer.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include "algorithms/common/status.hpp"

namespace bimslam::bim {
namespace {

using common::Error;
using common::StatusCode;

// The IFC base-64 alphabet (IfcGloballyUniqueId, IFC4 "8.7.3.2 IfcGloballyUniqueId"; it differs
// from RFC 4648: digits first, then upper, lower case, '_' and '$').
constexpr std::string_view kGuidAlphabet =
    "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$";

uint64_t SplitMix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

uint64_t Fnv1a64(std::string_view s) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (const char c : s) {
        h ^= static_cast<uint8_t>(c);
        h *= 0x100000001B3ull;
    }
    return h;
}

// Bits [top - n + 1, top] of the 128-bit number hi:lo, as an integer.
unsigned Bits(uint64_t hi, uint64_t lo, int top, int n) {
    unsigned v = 0;
    for (int i = top; i > top - n; --i) {
        const uint64_t bit = i >= 64 ? (hi >> (i - 64)) & 1u : (lo >> i) & 1u;
        v = (v << 1) | static_cast<unsigned>(bit);
    }
    return v;
}

std::string Upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    }
    return out;
}

}  // namespace

IfcWriter::IfcWriter(double length_unit_m, uint64_t seed)
    : length_unit_m_(length_unit_m), seed_(seed) {
    if (!(length_unit_m == 1.0 || length_unit_m == 0.01 || length_unit_m == 0.001)) {
        throw Error(StatusCode::kInvalidArgument,
                    "IfcWriter: length unit " + Real(length_unit_m) + " m is not 1, 0.01 or 0.001");
    }
}

IfcWriter::IfcWriter(AnyUnit, double length_unit_m, uint64_t seed, int first_id)
    : length_unit_m_(length_unit_m), seed_(seed), next_id_(first_id) {
    if (!(length_unit_m > 0) || !std::isfinite(length_unit_m) || first_id < 1) {
        throw Error(StatusCode::kInvalidArgument, "IfcWriter: length unit " + Real(length_unit_m) +
                                                      " m or first id " + std::to_string(first_id) +
                                                      " out of range");
    }
}

IfcWriter IfcWriter::Appending(double length_unit_m, uint64_t seed, int first_id) {
    return IfcWriter(AnyUnit{}, length_unit_m, seed, first_id);
}

int IfcWriter::Add(std::string_view name, std::string_view args) {
    const int id = next_id_++;
    data_ += '#';
    data_ += std::to_string(id);
    data_ += '=';
    data_ += Upper(name);
    data_ += '(';
    data_ += args;
    data_ += ");\n";
    return id;
}

std::string IfcWriter::Len(double metres) const {
    // Integer micrometres, then one correctly rounded division: 5.925 m is "5.925" and "5925.".
    const auto micro = static_cast<double>(std::llround(metres * 1e6));
    const auto per_unit = static_cast<double>(std::llround(length_unit_m_ * 1e6));
    return Real(micro / per_unit);
}

std::string IfcWriter::Real(double v) {
    if (v == 0.0) return "0.";  // also -0
    // ISO 10303-21 REAL: digits, a '.', optional fraction; no exponent needed for our magnitudes.
    std::array<char, 400> buf{};
    const auto [end, ec] =
        std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::fixed);
    if (ec != std::errc{})
        throw Error(StatusCode::kInvalidArgument, "IfcWriter: real out of range");
    std::string s(buf.data(), end);
    if (s.find('.') == std::string::npos) s += '.';
    return s;
}

std::string IfcWriter::Refs(const std::vector<int>& ids) {
    std::string s = "(";
    for (size_t i = 0; i < ids.size(); ++i) {
        if (i) s += ',';
        s += Ref(ids[i]);
    }
    return s + ")";
}

std::string IfcWriter::Str(std::string_view s) {
    if (s.empty()) return "$";
    std::string out = "'";
    for (const char c : s) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) {
            throw Error(
                StatusCode::kInvalidArgument,
                "IfcWriter: non-printable or non-ASCII character in '" + std::string(s) + "'");
        }
        // ISO 10303-21 7.3.3: an apostrophe is written twice, and so is a backslash.
        if (c == '\'' || c == '\\') out += c;
        out += c;
    }
    return out + "'";
}

std::string IfcWriter::GlobalId(uint64_t seed, std::string_view key) {
    const uint64_t hi = SplitMix64(seed ^ Fnv1a64(key));
    const uint64_t lo = SplitMix64(hi ^ SplitMix64(Fnv1a64(key) + 0x51ED270B7A3C1F2Dull));
    // 22 characters: the first holds the top 2 bits of the 128, each other one 6 bits.
    std::string id(22, '0');
    id[0] = kGuidAlphabet[Bits(hi, lo, 127, 2)];
    for (int k = 1; k < 22; ++k) id[k] = kGuidAlphabet[Bits(hi, lo, 125 - 6 * (k - 1), 6)];
    return id;
}

std::string IfcWriter::Guid(std::string_view key) {
    if (!keys_.insert(std::string(key)).second) {
        throw Error(StatusCode::kInternal,
                    "IfcWriter: GlobalId key '" + std::string(key) + "' used twice");
    }
    return "'" + GlobalId(seed_, key) + "'";
}

int IfcWriter::Point(const Eigen::Vector3d& m) {
    return Add("IfcCartesianPoint", "(" + Len(m.x()) + "," + Len(m.y()) + "," + Len(m.z()) + ")");
}

int IfcWriter::Point2(const Eigen::Vector2d& m) {
    return Add("IfcCartesianPoint", "(" + Len(m.x()) + "," + Len(m.y()) + ")");
}

int IfcWriter::Direction(const Eigen::Vector3d& r) {
    return Add("IfcDirection", "(" + Real(r.x()) + "," + Real(r.y()) + "," + Real(r.z()) + ")");
}

int IfcWriter::Placement(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& axis,
                         const Eigen::Vector3d& ref_direction) {
    const int location = Point(origin_m);
    if (axis == Eigen::Vector3d::UnitZ() && ref_direction == Eigen::Vector3d::UnitX()) {
        return Add("IfcAxis2Placement3D", Ref(location) + ",$,$");
    }
    const int z = Direction(axis);
    const int x = Direction(ref_direction);
    return Add("IfcAxis2Placement3D", Ref(location) + "," + Ref(z) + "," + Ref(x));
}

int IfcWriter::LocalPlacement(int relative_to, const Eigen::Vector3d& origin_m,
                              const Eigen::Vector3d& axis, const Eigen::Vector3d& ref_direction) {
    const int placement = Placement(origin_m, axis, ref_direction);
    return Add("IfcLocalPlacement",
               (relative_to > 0 ? Ref(relative_to) : std::string("$")) + "," + Ref(placement));
}

int IfcWriter::Box(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m) {
    const Eigen::Vector3d size = max_m - min_m;
    const Eigen::Vector2d centre = 0.5 * (min_m + max_m).head<2>();
    // IfcRectangleProfileDef(ProfileType, ProfileName, Position, XDim, YDim): centred on Position.
    const int profile_position = Add("IfcAxis2Placement2D", Ref(Point2(centre)) + ",$");
    const int profile = Add("IfcRectangleProfileDef", ".AREA.,$," + Ref(profile_position) + "," +
                                                          Len(size.x()) + "," + Len(size.y()));
    if (z_dir_ == 0) z_dir_ = Direction(Eigen::Vector3d::UnitZ());
    // IfcExtrudedAreaSolid(SweptArea, Position, ExtrudedDirection, Depth).
    const int position = Placement(Eigen::Vector3d(0, 0, min_m.z()));
    return Add("IfcExtrudedAreaSolid",
               Ref(profile) + "," + Ref(position) + "," + Ref(z_dir_) + "," + Len(size.z()));
}

int IfcWriter::Cylinder(const Eigen::Vector2d& centre_m, double radius_m, double z0_m,
                        double height_m) {
    // IfcCircleProfileDef(ProfileType, ProfileName, Position, Radius).
    const int profile_position = Add("IfcAxis2Placement2D", Ref(Point2(centre_m)) + ",$");
    const int profile =
        Add("IfcCircleProfileDef", ".AREA.,$," + Ref(profile_position) + "," + Len(radius_m));
    if (z_dir_ == 0) z_dir_ = Direction(Eigen::Vector3d::UnitZ());
    const int position = Placement(Eigen::Vector3d(0, 0, z0_m));
    return Add("IfcExtrudedAreaSolid",
               Ref(profile) + "," + Ref(position) + "," + Ref(z_dir_) + "," + Len(height_m));
}

int IfcWriter::Prism(const std::vector<Eigen::Vector2d>& polygon_m, int position, double depth_m) {
    std::vector<int> points;
    points.reserve(polygon_m.size() + 1);
    for (const Eigen::Vector2d& p : polygon_m) points.push_back(Point2(p));
    points.push_back(points.front());  // a closed IfcPolyline repeats its first point
    const int polyline = Add("IfcPolyline", Refs(points));
    // IfcArbitraryClosedProfileDef(ProfileType, ProfileName, OuterCurve).
    const int profile = Add("IfcArbitraryClosedProfileDef", ".AREA.,$," + Ref(polyline));
    if (z_dir_ == 0) z_dir_ = Direction(Eigen::Vector3d::UnitZ());
    if (position == 0) position = Placement(Eigen::Vector3d::Zero());
    return Add("IfcExtrudedAreaSolid",
               Ref(profile) + "," + Ref(position) + "," + Ref(z_dir_) + "," + Len(depth_m));
}

int IfcWriter::BodyShape(int context, const std::vector<int>& items) {
    // IfcShapeRepresentation(ContextOfItems, RepresentationIdentifier, RepresentationType, Items);
    // 'Body' / 'SweptSolid' as IFC4's "Body SweptSolid Geometry" concept prescribes.
    const int representation =
        Add("IfcShapeRepresentation", Ref(context) + ",'Body','SweptSolid'," + Refs(items));
    // IfcProductDefinitionShape(Name, Description, Representations).
    return Add("IfcProductDefinitionShape", "$,$,(" + Ref(representation) + ")");
}

std::string IfcWriter::Text(std::string_view file_name, std::string_view description) const {
    std::string out;
    out.reserve(data_.size() + 1024);
    out += "ISO-10303-21;\nHEADER;\n";
    // The Design Transfer View (IFC4 DTV): extruded solids with openings cut by boolean voids,
    // which is what this file holds (the Reference View expects tessellated geometry).
    out += "FILE_DESCRIPTION(('ViewDefinition [DesignTransferView_V1.0]'," + Str(description) +
           "),'2;1');\n";
    // FILE_NAME(name, time_stamp, author, organization, preprocessor_version,
    // originating_system, authorization): a fixed time stamp keeps the output deterministic.
    out += "FILE_NAME(" + Str(file_name) +
           ",'2024-01-01T00:00:00',('bimslam'),('bimslam'),'bimslam IfcWriter',"
           "'bimslam sample building generator','');\n";
    out += "FILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n";
    out += data_;
    out += "ENDSEC;\nEND-ISO-10303-21;\n";
    return out;
}

}  // namespace bimslam::bim
