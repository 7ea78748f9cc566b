// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/report/report_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <system_error>

#include "algorithms/common/status.hpp"
#include "algorithms/io/file_util.hpp"

namespace bimslam::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// One line of a CSV file as fields (RFC 4180 quoting, as change_report.cpp writes them).
std::vector<std::string> CsvFields(const std::string& line) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
            fields.back() += '"';
            ++i;
        } else if (c == '"') {
            quoted = !quoted;
        } else if (c == ',' && !quoted) {
            fields.emplace_back();
        } else if (c != '\r') {
            fields.back() += c;
        }
    }
    return fields;
}

struct Measured {
    int code = kNotObserved;
    double offset_m = 0;
    unsigned long support = 0;
};

int Code(const std::string& verdict, const fs::path& file) {
    if (verdict == "within") return kWithin;
    if (verdict == "beyond") return kBeyond;
    if (verdict == "not_observed") return kNotObserved;
    throw common::FileError(common::StatusCode::kParseError, file.string(), 0,
                            "tolerance_verdict '" + verdict + "'");
}

// Adds one recording's elements.csv; false when it has no tolerance verdicts (an older bimslam).
bool ReadElements(const fs::path& file, std::map<std::string, Measured>* out) {
    const std::string text = io::ReadFileToString(file);
    std::map<std::string, size_t> column;
    size_t start = 0;
    for (size_t line = 0; start < text.size(); ++line) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::vector<std::string> f = CsvFields(text.substr(start, end - start));
        start = end + 1;
        if (line == 0) {
            for (size_t k = 0; k < f.size(); ++k) column[f[k]] = k;
            for (const char* need :
                 {"global_id", "tolerance_verdict", "offset_m", "support_points"})
                if (!column.count(need)) return false;
            continue;
        }
        if (f.size() != column.size()) continue;  // the empty last line
        const auto get = [&](const char* name) { return f[column.at(name)]; };
        Measured m;
        const std::string id = get("global_id");
        try {
            m.code = Code(get("tolerance_verdict"), file);
            m.offset_m = std::stod(get("offset_m"));
            m.support = std::stoul(get("support_points"));
        } catch (const std::logic_error&) {
            throw common::FileError(common::StatusCode::kParseError, file.string(), line + 1,
                                    "a malformed number");
        }
        const auto it = out->find(id);
        const bool measured = m.code != kNotObserved;
        if (it == out->end()) {
            (*out)[id] = m;
        } else if (measured &&
                   (it->second.code == kNotObserved || m.support > it->second.support)) {
            it->second = m;
        }
    }
    return true;
}

}  // namespace

json ElementDeviations(const std::vector<fs::path>& change_dirs) {
    std::map<std::string, Measured> elements;
    double tolerance_m = 0;
    bool any = false;
    for (const fs::path& dir : change_dirs) {
        std::error_code ec;
        if (!fs::exists(dir / "elements.csv", ec) || !fs::exists(dir / "changes.json", ec))
            continue;
        const json c = json::parse(io::ReadFileToString(dir / "changes.json"));
        const json& p = c.at("parameters").at("elements");
        if (!p.contains("tolerance_m")) continue;
        if (!ReadElements(dir / "elements.csv", &elements)) continue;
        tolerance_m = p.at("tolerance_m").get<double>();  // the same for every recording of a run
        any = true;
    }
    if (!any) return nullptr;
    json rows = json::array();
    for (const auto& [id, m] : elements) {
        rows.push_back({id, m.code, std::round(m.offset_m * 1e5) / 1e5});  // 0.01 mm
    }
    return {{"tolerance_m", tolerance_m}, {"elements", rows}};
}

DistanceHistogram::DistanceHistogram(size_t storeys, double range_m, double bin_m)
    : range_m_(range_m),
      bin_m_(bin_m),
      counts_(std::max<size_t>(1, storeys),
              std::vector<uint64_t>(size_t(std::lround(2 * range_m / bin_m)), 0)),
      sum_(counts_.size(), 0),
      sum2_(counts_.size(), 0) {}

void DistanceHistogram::Add(int storey, float distance_m, int point_class) {
    if (point_class != 0 || !std::isfinite(distance_m)) return;  // 0: on the model
    const size_t s = size_t(std::clamp(storey, 0, int(counts_.size()) - 1));
    std::vector<uint64_t>& c = counts_[s];
    const double d = std::clamp(double(distance_m), -range_m_, range_m_);
    const size_t bin = std::min(c.size() - 1, size_t(std::floor((d + range_m_) / bin_m_)));
    ++c[bin];
    sum_[s] += distance_m;
    sum2_[s] += double(distance_m) * distance_m;
}

json DistanceHistogram::ToJson(const bim::BimModel& model) const {
    json storeys = json::array();
    for (size_t s = 0; s < counts_.size(); ++s) {
        uint64_t n = 0;
        for (const uint64_t c : counts_[s]) n += c;
        const double mean = n ? sum_[s] / double(n) : 0, rms = n ? std::sqrt(sum2_[s] / n) : 0;
        storeys.push_back({{"name", s < model.storeys.size() ? model.storeys[s].name : ""},
                           {"counts", counts_[s]},
                           {"points", n},
                           {"mean_cm", std::round(mean * 1e4) / 100},
                           {"rms_cm", std::round(rms * 1e4) / 100}});
    }
    return {{"bin_cm", bin_m_ * 100}, {"range_cm", range_m_ * 100}, {"storeys", storeys}};
}

}  // namespace bimslam::report
