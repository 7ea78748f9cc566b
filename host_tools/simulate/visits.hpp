// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// Visits over time (issue 33, item 7): a scenario's `visits` simulated one capture each, and the
// truth of what changed between them.
//
// OUT/<label>/ is each visit's complete capture (simulate.hpp: its own date in capture.json, its
// changes.json against the model, its scenario.yaml alone, so that `--scenario` on it reproduces
// it). OUT/visits.json lists the visits in date order and, for every pair of them (the consecutive
// ones marked), what changed from the earlier to the later:
//   objects (the added boxes, cylinders, meshes and mirrors, matched BY NAME; clutter is random
//   per visit and left out): `new` (in the later only), `gone` (in the earlier only), `moved`
//   (same name and shape, its reference point moved more than 1 cm or turned more than 1 degree:
//   the translation and yaw from the earlier place to the later), `unchanged`; a name whose shape
//   changed counts as gone and new;
//   elements: `newly_removed` (removed in the later, present in the earlier), `rebuilt` (removed
//   in the earlier, present again), `newly_moved` (placed differently: translation and yaw from
//   the earlier place to the later, an element moved back to its modelled place included).
// Each item carries the beams (beam_hits.hpp) each walk put on it: `beam_hits` (the later walk's)
// and `beam_hits_earlier`, so that scores count only what a walk saw. Where a thing is not in a
// visit, its count is of the beams that would have hit it first: a gone object's `beam_hits` is the
// later walk's on where it stood, a newly removed element's as in changes.json. A rebuilt element's
// `beam_hits` are the later walk's returns on it.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host_tools/bim/bim_model.hpp"
#include "host_tools/simulate/beam_hits.hpp"
#include "host_tools/simulate/scenario.hpp"
#include "host_tools/simulate/simulate.hpp"

namespace bimslam::simulate {

// A pose counts as changed beyond these (the "1 cm / 1 deg").
inline constexpr double kMovedTranslationM = 0.01;
inline constexpr double kMovedYawDeg = 1.0;

struct VisitCapture {
    std::string label;
    std::string date;
    CaptureReport report;
};

// The visits in date order (file order among equal dates).
std::vector<size_t> VisitsByDate(const Scenario& scenario);

// Simulates every visit of `scenario` into dir/<label>/ and writes dir/visits.json. `progress`
// gets the fraction of all visits done. Returns the captures in date order. Throws as
// SimulateCapture does, with the visit's label in the message.
std::vector<VisitCapture> SimulateVisits(const Scenario& scenario, const bim::BimModel& model,
                                         const std::string& model_sha256,
                                         const std::filesystem::path& dir,
                                         const std::function<void(double)>& progress = {});

// One simulated visit, as the pair truth reads it.
struct VisitTruth {
    std::string label;
    Scenario scenario;       // VisitScenario
    nlohmann::json changes;  // its changes.json
    // The beams of its walk on what the visits before it had and it lacks (VisitWatch): an
    // earlier visit's object now gone (by kind, name, shape and place), an element removed or
    // moved in an earlier visit (by GlobalId).
    std::map<std::string, size_t> watched_hits;
};

// What the walk of `later` is to watch for the pair truth: the objects of the `earlier` visits
// that it does not have (by name and shape, as they stood then), and the elements they removed
// or moved. Throws what reading a mesh file throws.
HitWatch VisitWatch(const std::vector<VisitTruth>& earlier, const Scenario& later);

// What changed from the earlier visit to the later (one entry of visits.json's `pairs`).
nlohmann::json VisitPairTruth(const VisitTruth& earlier, const VisitTruth& later);

}  // namespace bimslam::simulate
