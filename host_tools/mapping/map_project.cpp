// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/map_project.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/common/utc_time.hpp"
#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"
#include "drivers/net/packet_recording.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using common::FileError;
using common::StatusCode;
using nlohmann::json;

namespace {

constexpr size_t kHeadBytes = size_t(1) << 20;  // what identifies a recording with its size

json ToJson(const ProjectRecording& r) {
    json j = {{"name", r.name},
              {"path", r.path.string()},
              {"start", common::FormatUtcTime(r.start_ns)},
              {"start_ns", r.start_ns},
              {"start_from", r.start_from},
              {"identity", r.identity}};
    if (r.start) j["near"] = r.start->List();
    return j;
}

ProjectRecording RecordingFromJson(const json& j) {
    ProjectRecording r;
    r.name = j.at("name").get<std::string>();
    r.path = j.at("path").get<std::string>();
    r.start_ns = j.at("start_ns").get<int64_t>();
    r.start_from = j.at("start_from").get<std::string>();
    r.identity = j.at("identity");
    if (j.contains("near")) {
        const json& n = j.at("near");
        if (!n.is_array() || n.size() != 3) throw std::runtime_error("near: not [x, y, radius]");
        r.start = anchor::StartHint::FromList(n.get<std::vector<double>>());
    }
    return r;
}

void SortVisits(Project& p) {
    for (Visit& v : p.visits) {
        std::stable_sort(v.recordings.begin(), v.recordings.end(),
                         [](const auto& a, const auto& b) { return a.start_ns < b.start_ns; });
    }
    std::stable_sort(p.visits.begin(), p.visits.end(), [](const Visit& a, const Visit& b) {
        return a.start_ns() != b.start_ns() ? a.start_ns() < b.start_ns() : a.label < b.label;
    });
}

bool Exists(const fs::path& f) {
    std::error_code ec;
    return fs::exists(f, ec);
}

}  // namespace

fs::path VisitDir(const fs::path& out, const std::string& label) { return out / "visits" / label; }

void WriteIfChanged(const fs::path& file, const std::string& text) {
    std::error_code ec;
    if (fs::is_regular_file(file, ec) && fs::file_size(file, ec) == text.size() &&
        io::ReadFileToString(file) == text) {
        return;
    }
    io::WriteFileAtomic(file, text);
}

bool LoadProject(const fs::path& out, Project* project) {
    const fs::path file = out / "project.json";
    if (!Exists(file)) return false;
    try {
        const json j = json::parse(io::ReadFileToString(file));
        if (j.at("format") != "bimslam-map-project") throw std::runtime_error("not a project file");
        Project p;
        p.model = j.at("model").at("file").get<std::string>();
        p.model_sha256 = j.at("model").at("sha256").get<std::string>();
        for (const json& v : j.at("visits")) {
            Visit visit;
            visit.label = v.at("label").get<std::string>();
            visit.named = v.at("named").get<bool>();
            for (const json& r : v.at("recordings"))
                visit.recordings.push_back(RecordingFromJson(r));
            if (visit.recordings.empty())
                throw std::runtime_error("visit " + visit.label + ": no recording");
            p.visits.push_back(std::move(visit));
        }
        SortVisits(p);
        *project = std::move(p);
        return true;
    } catch (const std::exception& e) {
        throw FileError(
            StatusCode::kParseError, file.string(), 0,
            std::string("a damaged project file (") + e.what() +
                "): its visits' folders are kept; restore it, or map into a new folder");
    }
}

void SaveProject(const fs::path& out, const Project& project) {
    json visits = json::array();
    for (const Visit& v : project.visits) {
        json recs = json::array();
        for (const ProjectRecording& r : v.recordings) recs.push_back(ToJson(r));
        visits.push_back({{"label", v.label},
                          {"named", v.named},
                          {"start", common::FormatUtcTime(v.start_ns())},
                          {"start_ns", v.start_ns()},
                          {"dir", (fs::path("visits") / v.label).string()},
                          {"recordings", recs}});
    }
    const json j = {{"format", "bimslam-map-project"},
                    {"version", 1},
                    {"model", {{"file", project.model.string()}, {"sha256", project.model_sha256}}},
                    {"visits", visits}};
    fs::create_directories(out);
    WriteIfChanged(out / "project.json", j.dump(2) + "\n");
}

ProjectRecording DescribeRecording(const RecordingInput& input) {
    ProjectRecording r;
    r.name = input.name;
    r.path = fs::absolute(input.path).lexically_normal();
    const fs::path& packets = input.files.packets;
    net::PacketRecording recording(packets);
    net::UdpDatagram first;
    if (!recording.Next(first)) {
        throw FileError(StatusCode::kParseError, packets.string(), 0, "no packet: no date-time");
    }
    std::ifstream in(packets, std::ios::binary);
    std::string head(kHeadBytes, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(in.gcount()));
    r.identity = {{"size", fs::file_size(packets)},
                  {"first_packet_ns", first.timestamp_ns},
                  {"head_sha256", io::Sha256Hex(head)}};
    r.start_ns = first.timestamp_ns;
    r.start_from = "first packet";
    if (!input.files.capture_json.empty()) {
        json manifest;
        try {
            manifest = json::parse(io::ReadFileToString(input.files.capture_json));
        } catch (const json::exception& e) {
            throw FileError(StatusCode::kParseError, input.files.capture_json.string(), 0,
                            e.what());
        }
        if (manifest.contains("start_ns") && manifest["start_ns"].is_number_integer()) {
            r.start_ns = manifest["start_ns"].get<int64_t>();
            r.start_from = "capture.json";
        }
    }
    return r;
}

void CheckVisitLabel(const std::string& label) {
    const bool ok =
        !label.empty() && label.size() <= 64 && label[0] != '.' &&
        std::all_of(label.begin(), label.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
        });
    if (!ok) {
        common::ThrowInvalid("--visit '" + label +
                             "': a visit's label names its folder: letters, digits, '-', '_' "
                             "and '.', not first, at most 64 characters");
    }
}

namespace {
// A recording of the project whose path now holds another recording (re-recorded in place) is
// no longer in the project: the new one is added as any other (its visit by its date; a visit
// left with no recording is dropped from project.json, its folder left as it is).
void DropReplaced(Project& project, const ProjectRecording& r, std::set<std::string>* names,
                  std::vector<std::string>* notes) {
    for (Visit& v : project.visits) {
        for (auto k = v.recordings.begin(); k != v.recordings.end(); ++k) {
            if (k->path != r.path || k->identity == r.identity) continue;
            notes->push_back(r.path.string() + ": not the recording " + k->name + " of visit " +
                             v.label + " any more (another size, first packet or first MiB): " +
                             "mapped as a new recording");
            names->erase(k->name);
            v.recordings.erase(k);
            break;
        }
    }
    std::erase_if(project.visits, [](const Visit& v) { return v.recordings.empty(); });
}

// The recording of the project that `r` is (the same identity), given again: it keeps its visit
// and name and takes the path given now. False when `r` is new.
bool TakeKnown(Project& project, const ProjectRecording& r, bool adding, RecordingInput& in,
               std::vector<std::string>* notes) {
    for (Visit& v : project.visits) {
        for (ProjectRecording& k : v.recordings) {
            if (k.identity != r.identity) continue;
            if (r.start) k.start = r.start;
            if (k.path != r.path) {
                notes->push_back(r.path.string() + ": the recording " + k.name + " of visit " +
                                 v.label +
                                 " (the same size, first packet and first MiB), moved "
                                 "or copied: its path is now this one");
                k.path = r.path;
            } else if (adding) {
                notes->push_back(r.path.string() + ": already in visit " + v.label + " (as " +
                                 k.name + "), not added again");
            }
            in.name = k.name;
            return true;
        }
    }
    return false;
}

// The visit `label` (named by --visit or a day's), made when there is none.
Visit& VisitFor(Project& project, const std::string& label, bool named) {
    for (Visit& v : project.visits) {
        if (v.label != label) continue;
        if (v.named != named) {
            common::ThrowInvalid("visit " + label + ": the label of a visit " +
                                 (named ? "of that day" : "named by --visit") +
                                 " already: give --visit another label");
        }
        return v;
    }
    return project.visits.emplace_back(Visit{label, named, {}});
}
}  // namespace

void AddRecordings(Project& project, std::vector<RecordingInput>& inputs,
                   const std::string& visit_label, bool adding,
                   const std::optional<anchor::StartHint>& start, std::vector<std::string>* notes) {
    std::set<std::string> names;
    for (const Visit& v : project.visits)
        for (const ProjectRecording& r : v.recordings) names.insert(r.name);
    for (RecordingInput& in : inputs) {
        ProjectRecording r = DescribeRecording(in);
        r.start = start;
        DropReplaced(project, r, &names, notes);
        if (TakeKnown(project, r, adding, in, notes)) continue;
        // A new recording: a name no other recording of the project has, its day's visit or
        // the one --visit names.
        std::string name = r.name;
        for (int k = 2; names.count(name); ++k) name = r.name + "_" + std::to_string(k);
        names.insert(name);
        r.name = in.name = name;
        const bool named = !visit_label.empty();
        VisitFor(project, named ? visit_label : common::FormatUtcDay(r.start_ns), named)
            .recordings.push_back(std::move(r));
    }
    SortVisits(project);
}

void CheckVisitFolder(const fs::path& out, const Visit& visit) {
    const fs::path dir = VisitDir(out, visit.label);
    const auto damaged = [&](const std::string& what) {
        return FileError(StatusCode::kDataLoss, dir.string(), 0,
                         "visit " + visit.label + " is damaged: " + what +
                             "; the other visits are kept: remove this folder to process the "
                             "visit again");
    };
    // A file a stamp says its step wrote: it must be there and, for JSON, parse.
    const auto need = [&](const fs::path& rel, bool is_json) -> json {
        const fs::path f = dir / rel;
        if (!Exists(f)) throw damaged(rel.string() + " is missing (its step's stamp is there)");
        if (!is_json) return nullptr;
        try {
            return json::parse(io::ReadFileToString(f));
        } catch (const std::exception& e) {
            throw damaged(rel.string() + " is unreadable (" + e.what() + ")");
        }
    };
    const auto stamped = [&](const std::string& step) {
        return Exists(dir / "stamps" / (step + ".json"));
    };
    for (const ProjectRecording& r : visit.recordings) {
        if (!stamped("odometry_" + r.name)) continue;
        need(fs::path("odometry") / (r.name + ".json"), true);
        need(fs::path("odometry") / r.name / "session.json", true);
    }
    if (!stamped("anchor")) return;
    const json anchor = need(fs::path("anchor") / "anchor.json", true);
    std::vector<std::string> anchored;
    try {
        for (const json& q : anchor.at("sessions")) {
            if (q.at("verdict") == "anchored" || q.at("verdict") == "anchored-in-parts")
                anchored.push_back(q.at("name").get<std::string>());
        }
    } catch (const json::exception& e) {
        throw damaged(std::string("anchor/anchor.json is unreadable (") + e.what() + ")");
    }
    for (const std::string& name : anchored) {
        need(fs::path("anchor") / name / "trajectory_bim.tum", false);
        need(fs::path("anchor") / name / "optimized_poses.txt", false);
    }
    if (!stamped("changes")) return;
    for (const std::string& name : anchored)
        need(fs::path("changes") / name / "changes.json", true);
}

ProjectInputs OpenProject(const fs::path& out, const fs::path& model_given,
                          const std::vector<fs::path>& recordings, const std::string& visit,
                          bool adding, const std::optional<anchor::StartHint>& start) {
    ProjectInputs p;
    const bool exists = LoadProject(out, &p.project);
    if (model_given.empty() && !exists) {
        throw common::FileError(common::StatusCode::kNotFound, out.string(), 0,
                                "not a `bimslam map` project (no project.json): map a model and "
                                "recordings into it first");
    }
    if (!exists && recordings.empty()) common::ThrowInvalid("no recording given");
    const fs::path model =
        model_given.empty() ? p.project.model : fs::absolute(model_given).lexically_normal();
    CheckModelFile(model);
    const std::string sha256 = io::Sha256File(model);
    if (exists && sha256 != p.project.model_sha256) {
        p.notes.push_back(model.string() +
                          ": not the model the project's visits were mapped against (its "
                          "SHA-256 differs): every visit is processed again");
    }
    p.project.model = model;
    p.project.model_sha256 = sha256;
    if (!visit.empty()) CheckVisitLabel(visit);
    std::vector<RecordingInput> given = CheckRecordings(recordings);
    AddRecordings(p.project, given, visit, adding, start, &p.notes);
    for (const Visit& v : p.project.visits) {
        std::vector<RecordingInput>& inputs = p.visits.emplace_back();
        for (const ProjectRecording& r : v.recordings) {
            auto g = std::find_if(given.begin(), given.end(),
                                  [&](const RecordingInput& x) { return x.name == r.name; });
            inputs.push_back(g != given.end() ? *g : CheckRecordings({r.path}).front());
            inputs.back().name = r.name;
        }
    }
    return p;
}

}  // namespace bimslam::mapping
