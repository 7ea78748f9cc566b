// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Internal to the IFC ingest (ifc_model.cpp, ifc_geometry.cpp), the only code that includes IFC++:
// what IFC++ reports while a file loads, and the geometry of its products as triangles in metres.
// IFC++'s classes are only forward-declared here, so this header pulls in none of its headers.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

class BuildingModel;  // IFC++ (global namespace)
class IfcProduct;
class StatusCallback;

namespace bimslam::bim::ifc {

// What IFC++ says while one file loads: its messages (warnings and errors, not its progress) and
// whatever it prints, deduplicated. IFC++ reports through callbacks and, in places, std::cout.
class MessageLog {
public:
    static constexpr size_t kMaxKept = 300;

    // `subject` is "<class> <GlobalId>" while one product converts, else empty.
    void Add(const std::string& text);
    void SetSubject(std::string subject);
    // The first message about the current subject since SetSubject.
    const std::string& subject_first() const { return subject_first_; }
    // A face IFC++ could not triangulate and dropped (its entity id), from its message.
    void AddLostFace(int face_id);
    // The faces lost since SetSubject, in the order reported, each once.
    const std::vector<int>& subject_lost_faces() const { return subject_lost_faces_; }

    std::vector<std::string> kept;  // distinct messages, at most kMaxKept
    size_t count = 0;               // every message, repeats included
    // Called with IFC++'s parse progress in [0, 1].
    std::function<void(double)> parse_progress;
    std::set<int> lost_faces;  // every face lost while this log listened

private:
    std::set<std::string> seen_;
    std::string subject_, subject_first_;
    std::vector<int> subject_lost_faces_;
};

// Routes a StatusCallback's (reader, model, converter) messages and progress into `log`.
void ListenTo(StatusCallback& source, MessageLog& log);

// While alive, the standard C++ streams (narrow and wide) write into buffers instead of the
// terminal; on destruction each captured line goes to the log. IFC++ and carve print diagnostics
// with std::cout and std::wcout, and writing to std::wcout would also switch stdout to wide
// orientation for the rest of the process. Not thread-safe: the streams are process-global.
class QuietStreams {
public:
    explicit QuietStreams(MessageLog& log);
    ~QuietStreams();
    QuietStreams(const QuietStreams&) = delete;
    QuietStreams& operator=(const QuietStreams&) = delete;

private:
    MessageLog& log_;
    std::stringstream narrow_;
    std::wstringstream wide_;
    std::streambuf *cout_, *cerr_, *clog_;
    std::wstreambuf *wcout_, *wcerr_, *wclog_;
};

// UTF-8 of IFC++'s wide strings (UTF-32 on Linux).
std::string Utf8(const std::wstring& text);

// One product's geometry in the model's world coordinates, metres. Vertices are its own.
struct ProductMesh {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
    // It has a representation meant as a 3D body (identifier "Body", or a solid or surface type);
    // products with only axes, footprints or annotations have no body and have not failed.
    bool expects_body = false;
    std::string error;  // why there is no geometry (an exception, IFC++'s first message)
    // Faces (IfcFace entity ids) IFC++ could not triangulate: the mesh lacks them.
    std::vector<int> lost_faces;
};

// IFC++'s geometry converter (carve CSG) for one loaded model.
class Geometry {
public:
    Geometry(std::shared_ptr<BuildingModel> model, int vertices_per_circle, MessageLog& log);
    ~Geometry();
    Geometry(const Geometry&) = delete;
    Geometry& operator=(const Geometry&) = delete;

    // World height (metres) of a product's placement origin, if it has a placement.
    std::optional<double> PlacementZ(const std::shared_ptr<IfcProduct>& product);
    // The products' meshes (same order): placed in the world, openings subtracted, faces
    // triangulated. `progress` gets [0, 1]. Never throws for one product's failure.
    std::vector<ProductMesh> Convert(const std::vector<std::shared_ptr<IfcProduct>>& products,
                                     const std::function<void(double)>& progress);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace bimslam::bim::ifc
