// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Mesh files for added objects: PLY through algorithms/io, OBJ read here (Wavefront OBJ: "v x y z"
// and "f a b c ..." lines with 1-based or negative indices, optionally "a/t/n"; polygons are fan
// triangulated; every other statement is ignored).
#include <charconv>
#include <sstream>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/ply.hpp"
#include "host_tools/simulate/world.hpp"

namespace bimslam::simulate {
namespace {

common::TriangleMesh ParseObj(const std::string& name, const std::string& text) {
    common::TriangleMesh m;
    std::istringstream in(text);
    std::string line;
    size_t number = 0;
    auto fail = [&](const std::string& what) {
        throw common::FileError(common::StatusCode::kParseError, name, number,
                                what + ": '" + line + "'");
    };
    while (std::getline(in, line)) {
        ++number;
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            Eigen::Vector3d p;
            if (!(ls >> p.x() >> p.y() >> p.z()) || !p.allFinite())
                fail("a vertex needs 3 finite numbers");
            m.vertices.push_back(p.cast<float>());
        } else if (tag == "f") {
            std::vector<uint32_t> corners;
            std::string item;
            while (ls >> item) {
                long index = 0;
                const auto [end, ec] =
                    std::from_chars(item.data(), item.data() + item.size(), index);
                if (ec != std::errc() || (end != item.data() + item.size() && *end != '/')) {
                    fail("a face index is not an integer");
                }
                const long n = long(m.vertices.size());
                const long i = index > 0 ? index - 1 : n + index;  // negative: relative to the end
                if (index == 0 || i < 0 || i >= n) fail("a face index is out of range");
                corners.push_back(uint32_t(i));
            }
            if (corners.size() < 3) fail("a face needs at least 3 corners");
            for (size_t k = 1; k + 1 < corners.size(); ++k) {
                m.triangles.push_back({corners[0], corners[k], corners[k + 1]});
            }
        }
    }
    if (m.triangles.empty()) {
        line.clear();
        fail("no faces");
    }
    return m;
}

}  // namespace

common::TriangleMesh LoadMeshFile(const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return ParseObj(file.string(), io::ReadFileToString(file));
    if (ext != ".ply") {
        throw common::FileError(common::StatusCode::kInvalidArgument, file.string(), 0,
                                "a mesh must be a .ply or .obj file");
    }
    common::TriangleMesh m;
    try {
        m = io::MeshFromPly(io::ReadPly(file));
    } catch (const common::FileError&) {
        throw;
    } catch (const common::Error& e) {
        throw common::FileError(e.code(), file.string(), 0, e.what());
    }
    if (m.triangles.empty()) {
        throw common::FileError(common::StatusCode::kInvalidArgument, file.string(), 0,
                                "the mesh has no faces");
    }
    return m;
}

}  // namespace bimslam::simulate
