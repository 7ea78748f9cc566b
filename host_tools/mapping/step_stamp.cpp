// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/step_stamp.hpp"

#include <elf.h>
#include <link.h>

#include <chrono>
#include <cstring>
#include <system_error>

#include "algorithms/io/file_util.hpp"
#include "algorithms/io/sha256.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;

namespace {

// The program's GNU build ID (the linker's hash of its output, `readelf -n`: the note
// NT_GNU_BUILD_ID named "GNU" in a PT_NOTE segment), hex; empty when it has none.
std::string GnuBuildId() {
    std::string id;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* out) -> int {
            for (int i = 0; i < info->dlpi_phnum; ++i) {
                const ElfW(Phdr)& ph = info->dlpi_phdr[i];
                if (ph.p_type != PT_NOTE) continue;
                const size_t align = ph.p_align == 8 ? 8 : 4;  // gABI: note entries' alignment
                const auto pad = [align](size_t n) { return (n + align - 1) & ~(align - 1); };
                const char* p = reinterpret_cast<const char*>(info->dlpi_addr + ph.p_vaddr);
                const char* end = p + ph.p_memsz;
                while (p + sizeof(ElfW(Nhdr)) <= end) {
                    const auto* n = reinterpret_cast<const ElfW(Nhdr)*>(p);
                    const char* name = p + sizeof(ElfW(Nhdr));
                    const char* desc = name + pad(n->n_namesz);
                    if (desc + n->n_descsz > end) break;
                    if (n->n_type == NT_GNU_BUILD_ID && n->n_namesz == 4 &&
                        std::memcmp(name, "GNU", 4) == 0) {
                        static const char* hex = "0123456789abcdef";
                        auto* s = static_cast<std::string*>(out);
                        for (size_t k = 0; k < n->n_descsz; ++k) {
                            const auto b = static_cast<unsigned char>(desc[k]);
                            s->push_back(hex[b >> 4]);
                            s->push_back(hex[b & 15]);
                        }
                        return 1;
                    }
                    p = desc + pad(n->n_descsz);
                }
            }
            return 1;  // the first object is the program itself; its libraries do not matter
        },
        &id);
    return id;
}

}  // namespace

const std::string& StepStamp::Program() {
    // Once per process. Without a build ID (a linker told not to write one), the executable's
    // SHA-256 stands in: the same build, the same identity.
    static const std::string program = [] {
        const std::string id = GnuBuildId();
        if (!id.empty()) return "build-id " + id;
        std::error_code ec;
        const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
        return ec ? std::string("unknown") : "sha256 " + io::Sha256File(exe);
    }();
    return program;
}

StepStamp::StepStamp(std::string step) {
    json_ = {{"format", "bimslam-map-stamp"},
             {"version", 1},
             {"step", std::move(step)},
             {"program", Program()},
             {"inputs", nlohmann::json::object()},
             {"upstream", nlohmann::json::object()},
             {"parameters", nlohmann::json::object()}};
}

void StepStamp::AddFileContent(const std::string& key, const fs::path& file) {
    // By content only: the same model copied or touched is the same model.
    json_["inputs"][key] = {{"sha256", io::Sha256File(file)}};
}

void StepStamp::AddFileTime(const std::string& key, const fs::path& file) {
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    // Not the path: a project moved with its recordings (or copied with their times, `cp -a`)
    // is the same project, and its steps are not done again. Which file is which the project
    // knows by the recording's identity (map_project.hpp); a file of the same size and time to
    // the nanosecond that is another recording is not a case worth hashing gigabytes for.
    nlohmann::json j = nlohmann::json::object();
    if (ec) {
        j["missing"] = true;
    } else {
        j["size"] = size;
        j["mtime_ns"] = fs::last_write_time(file, ec).time_since_epoch().count();
    }
    json_["inputs"][key] = j;
}

void StepStamp::AddUpstream(const StepStamp& upstream) {
    json_["upstream"][upstream.json_["step"].get<std::string>()] = upstream.Digest();
}

void StepStamp::AddParameter(const std::string& key, nlohmann::json value) {
    json_["parameters"][key] = std::move(value);
}

std::string StepStamp::Digest() const {
    // Without the program: which build made a step is said (MadeByThisProgram), not a reason to
    // make the steps after it again; and the stamps made before it was named keep their digests.
    nlohmann::json j = json_;
    j.erase("program");
    return io::Sha256Hex(j.dump());
}

bool StepStamp::Matches(const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return false;
    try {
        nlohmann::json stored = nlohmann::json::parse(io::ReadFileToString(file));
        if (!stored.is_object() || !stored.contains("made")) return false;
        const nlohmann::json made = stored["made"];
        // A stamp of before stop 62 names no program: another build, as far as anyone knows.
        const std::string program = stored.value("program", std::string());
        nlohmann::json mine = json_;
        for (nlohmann::json* j : {&stored, &mine}) {
            j->erase("made");
            j->erase("program");
        }
        if (stored != mine) return false;
        // Kept as it was made: its token (which the stamps after it hold through its digest) and
        // its program, which the digest leaves out.
        json_["made"] = made;
        json_["program"] = program;
        return true;
    } catch (const std::exception&) {
        return false;  // unreadable or not JSON: the step runs again and rewrites it
    }
}

void StepStamp::MarkMade() {
    json_["made"] = std::chrono::system_clock::now().time_since_epoch().count();
}

void StepStamp::Write(const fs::path& file) const {
    io::WriteFileAtomic(file, json_.dump(2) + "\n");
}

}  // namespace bimslam::mapping
