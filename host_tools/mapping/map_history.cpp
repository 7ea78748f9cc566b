// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
#include "host_tools/mapping/map_history.hpp"

#include <algorithm>
#include <map>
#include <optional>

#include "algorithms/common/utc_time.hpp"
#include "host_tools/mapping/object_tracks.hpp"

namespace bimslam::mapping {
namespace fs = std::filesystem;
using change_detection::FoundChanges;
using nlohmann::json;

json HistoryConfig::ToJson() const {
    return {{"same_min_iou", same_min_iou},
            {"same_max_centroid_m", same_max_centroid_m},
            {"part_min_inside", part_min_inside},
            {"part_margin_m", part_margin_m},
            {"moved_max_m", moved_max_m},
            {"shape_tolerance", shape_tolerance},
            {"shape_tolerance_m", shape_tolerance_m},
            {"volume_tolerance", volume_tolerance},
            {"cell_m", cell_m},
            {"floor_band_m", floor_band_m},
            {"min_floor_seen", min_floor_seen},
            {"min_cells", min_cells}};
}

namespace {

bool Observed(const std::string& verdict) { return verdict != "not_observed"; }
bool Built(const std::string& verdict) { return verdict == "confirmed" || verdict == "deviating"; }

// Merges one recording's findings into its visit's (ReadVisitFindings's rules).
void Merge(const std::string& recording, FoundChanges&& f, const HistoryConfig& config,
           VisitFindings* findings) {
    FoundChanges* visit = &findings->found;
    for (auto& [id, e] : f.elements) {
        auto [it, inserted] = visit->elements.emplace(id, e);
        if (inserted || !Observed(e.verdict)) continue;
        if (!Observed(it->second.verdict) || e.expected_area_m2 > it->second.expected_area_m2)
            it->second = e;
    }
    for (FoundChanges::Object& o : f.objects) {
        const bool known = std::any_of(
            visit->objects.begin(), visit->objects.end(),
            [&](const FoundChanges::Object& k) { return SamePlace(k.box, o.box, config); });
        if (known) continue;
        visit->objects.push_back(std::move(o));
        findings->object_recordings.push_back(recording);
    }
    visit->map.insert(visit->map.end(), f.map.begin(), f.map.end());
    visit->has_map = visit->has_map || f.has_map;
}

// One element over the visits: its verdict in each (nullptr: not in that visit's files).
struct ElementRow {
    const FoundChanges::Element* any = nullptr;  // for its class, name and storey
    std::vector<const FoundChanges::Element*> visits;
};

std::map<std::string, ElementRow> ElementRows(const std::vector<VisitFindings>& visits) {
    std::map<std::string, ElementRow> rows;
    for (size_t v = 0; v < visits.size(); ++v) {
        for (const auto& [id, e] : visits[v].found.elements) {
            ElementRow& row = rows[id];
            row.visits.resize(visits.size(), nullptr);
            row.visits[v] = &e;
            if (!row.any) row.any = &e;
        }
    }
    return rows;
}

// The last visit before `v` that observed the element, if any.
std::optional<size_t> LastObserved(const ElementRow& row, size_t v) {
    for (size_t k = v; k-- > 0;) {
        if (row.visits[k] && Observed(row.visits[k]->verdict)) return k;
    }
    return std::nullopt;
}

json ElementJson(const std::string& id, const ElementRow& row,
                 const std::vector<VisitFindings>& visits) {
    json verdicts = json::array(), deviations = json::array();
    json first = nullptr, last = nullptr, last_observed = nullptr, last_verdict = "not_observed";
    for (size_t v = 0; v < visits.size(); ++v) {
        const FoundChanges::Element* e = row.visits[v];
        const std::string verdict = e ? e->verdict : "not_observed";
        verdicts.push_back(verdict);
        if (!Observed(verdict)) continue;
        last_observed = visits[v].label;
        last_verdict = verdict;
        if (Built(verdict)) {
            if (first.is_null()) first = visits[v].label;
            last = visits[v].label;
        }
        if (verdict == "deviating") {
            deviations.push_back({{"visit", visits[v].label},
                                  {"offset_m", Vec(e->offset)},
                                  {"offset_norm_m", e->offset.norm()},
                                  {"moved", e->moved},
                                  {"moved_yaw_deg", e->moved_yaw_deg}});
        }
    }
    return {{"global_id", id},
            {"class", row.any->ifc_class},
            {"name", row.any->name},
            {"storey", row.any->storey},
            {"verdicts", verdicts},
            {"first_seen_built", first},
            {"last_seen_built", last},
            {"last_observed", last_observed},
            {"last_verdict", last_verdict},
            {"deviations", deviations}};
}

// The elements' part of visit v's changes since the previous visit (each element against the
// last earlier visit that observed it) and the contradictions it shows.
void ElementChanges(const std::map<std::string, ElementRow>& rows,
                    const std::vector<VisitFindings>& visits, size_t v, json* since_previous,
                    json* contradictions) {
    json newly_missing = json::array(), newly_deviating = json::array(), reappeared = json::array(),
         in_place_again = json::array();
    for (const auto& [id, row] : rows) {
        const FoundChanges::Element* now = row.visits[v];
        const std::optional<size_t> before = LastObserved(row, v);
        if (!now || !Observed(now->verdict) || !before) continue;
        const std::string& was = row.visits[*before]->verdict;
        const std::string& is = now->verdict;
        if (Built(was) && is == "missing") newly_missing.push_back(id);
        if (was == "confirmed" && is == "deviating") newly_deviating.push_back(id);
        const bool back =
            (was == "missing" && Built(is)) || (was == "deviating" && is == "confirmed");
        if (!back) continue;
        (was == "missing" ? reappeared : in_place_again).push_back(id);
        contradictions->push_back({{"global_id", id},
                                   {"visit", visits[*before].label},
                                   {"verdict", was},
                                   {"contradicted_by", visits[v].label},
                                   {"by_verdict", is}});
    }
    (*since_previous)["newly_missing"] = newly_missing;
    (*since_previous)["newly_deviating"] = newly_deviating;
    (*since_previous)["reappeared"] = reappeared;
    (*since_previous)["in_place_again"] = in_place_again;
}

// What differs from the model as of visit v: each element's last observed verdict up to v.
json ElementsSinceModel(const std::map<std::string, ElementRow>& rows,
                        const std::vector<VisitFindings>& visits, size_t v) {
    json missing = json::array(), deviating = json::array();
    for (const auto& [id, row] : rows) {
        const std::optional<size_t> at = LastObserved(row, v + 1);
        if (!at) continue;
        const FoundChanges::Element& e = *row.visits[*at];
        if (e.verdict == "missing") {
            missing.push_back({{"global_id", id}, {"as_of", visits[*at].label}});
        } else if (e.verdict == "deviating") {
            deviating.push_back(
                {{"global_id", id}, {"as_of", visits[*at].label}, {"offset_m", Vec(e.offset)}});
        }
    }
    return {{"missing", missing}, {"deviating", deviating}};
}

}  // namespace

VisitFindings ReadVisitFindings(const fs::path& visit_dir, const std::string& label,
                                int64_t start_ns) {
    VisitFindings v;
    v.label = label;
    v.start_ns = start_ns;
    const fs::path changes = visit_dir / "changes";
    if (!fs::is_directory(changes)) return v;
    std::vector<fs::path> dirs;
    for (const auto& e : fs::directory_iterator(changes)) {
        if (e.is_directory() && fs::exists(e.path() / "changes.json")) dirs.push_back(e.path());
    }
    std::sort(dirs.begin(), dirs.end());
    const HistoryConfig config;
    for (const fs::path& d : dirs) {
        v.recordings.push_back(d.filename().string());
        Merge(d.filename().string(), change_detection::ReadFoundChanges(d), config, &v);
    }
    return v;
}

json BuildHistory(const std::vector<VisitFindings>& visits, const HistoryConfig& config) {
    const std::map<std::string, ElementRow> rows = ElementRows(visits);
    ObjectTracks objects(config);
    json visits_json = json::array(), changes = json::array(), contradictions = json::array();
    for (size_t v = 0; v < visits.size(); ++v) {
        const VisitFindings& visit = visits[v];
        visits_json.push_back({{"label", visit.label},
                               {"start", common::FormatUtcTime(visit.start_ns)},
                               {"recordings", visit.recordings},
                               {"new_objects", visit.found.objects.size()}});
        json since_previous = objects.Update(v, visit);
        ElementChanges(rows, visits, v, &since_previous, &contradictions);
        json since_model = ElementsSinceModel(rows, visits, v);
        since_model["new_objects"] = objects.Present(visits);
        changes.push_back({{"visit", visit.label},
                           {"previous", v ? json(visits[v - 1].label) : json(nullptr)},
                           {"since_previous", v ? since_previous : json(nullptr)},
                           {"since_model", since_model}});
    }
    json elements = json::array();
    for (const auto& [id, row] : rows) elements.push_back(ElementJson(id, row, visits));
    return {{"format", "bimslam-history"},
            {"version", 1},
            {"frame", "bim"},
            {"parameters", config.ToJson()},
            {"visits", visits_json},
            {"elements", elements},
            {"objects", objects.ToJson(visits)},
            {"changes", changes},
            {"contradictions", contradictions}};
}

json HistoryCounts(const json& history) {
    json counts = {{"visits", history.at("visits").size()},
                   {"contradictions", history.at("contradictions").size()}};
    const json& changes = history.at("changes");
    if (changes.empty()) return counts;
    const json& newest = changes.back();
    counts["visit"] = newest.at("visit");
    if (newest.at("since_previous").is_object()) {
        json since = {{"previous", newest.at("previous")}};
        for (const auto& [k, list] : newest.at("since_previous").items()) since[k] = list.size();
        counts["since_previous"] = since;
    }
    json model;
    for (const auto& [k, list] : newest.at("since_model").items()) model[k] = list.size();
    counts["since_model"] = model;
    return counts;
}

}  // namespace bimslam::mapping
