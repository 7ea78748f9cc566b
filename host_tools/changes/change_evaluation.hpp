// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// `bimslam changes --truth`: a run's changes.json and elements.csv against the simulator's ground
// truth (a capture's changes.json, host_tools/simulate/world.hpp), the scores of issue 13:
//   added objects     precision, recall, F1; a found object matches a true one (one to one,
//                     best first) when their boxes' 3D IoU >= 0.25 or their centres are within
//                     0.3 m, the true one's box being its whole box or, with the run's map, the
//                     box of the map points on it ("seen", below: the part the walk saw; a
//                     bookcase seen from its door is its face, 0.6 m from its centre). "large":
//                     true objects of at least 0.3 m (largest extent) for recall, found objects of
//                     at least 0.3 m for precision (a small true object found counts for neither;
//                     one found large but not true counts against). "separable": the same with true
//                     objects whose surfaces come within touch_m (one map voxel, 5 cm) of each
//                     other taken as one (their union box): objects placed by hand may touch, and
//                     no 5 cm map separates them (the simulator's random clutter keeps 5 cm clear
//                     of other objects). Needs the truth's meshes (changes/*.ply beside its
//                     changes.json).
//   removed elements  recall and precision by GlobalId against the elements found missing; "large":
//                     those with at least 1 m^2 of expected visible surface (elements.csv).
//   moved elements    found (deviating with a fitted motion), the error of the translation and yaw.
//   as-built walls    the measured offset against the true one (vector difference), for the walls
//                     the session saw (support >= 30 points) and that were not surveyed (a wall
//                     in `parameters.refinement.datum` is measured to its survey: counted apart).
//   seen              (issue 31, item 8) the scores of what the walk's keyframes saw, which is
//                     all change detection maps: a true added object is "in view" when the run's
//                     map (map_bim.ply: the keyframes' points at the refined poses, one per 5 cm
//                     voxel) has at least the detector's smallest object (`min_object_points`, 30)
//                     of points on it (within on_object_m of its surface, nearer to it than to
//                     the model and farther than `band_threshold_m`, 5 cm, from the model: a
//                     nearer point the detector takes for the model's surface), of which at least
//                     `min_multi_view_fraction` (a quarter) were seen by two keyframes or more:
//                     less than that the detector cannot call an object (algorithms/changes/
//                     README.md, step 4). A removed element is in view
//                     when the keyframes' beams reached at least `min_judged_area_m2` (0.25 m^2)
//                     of where it stood (elements.csv expected_area_m2; below it the detector says
//                     not_observed). Thresholds are the run's own (changes.json parameters). The
//                     "seen" scores count only objects in view in recall (precision is the same: a
//                     found object that matches one out of view is no false alarm), say how many
//                     were out of view and, of those, how many no beam of any scan hit (the
//                     simulator's `beam_hits`), and list every object's figures. A run without
//                     map_bim.ply: every object in view.
//   people            found objects that match no added object and lie in a person's path (its
//                     line widened by radius + 0.3 m, from its floor to its height): should be
//                     none; people with a transient cluster on their line.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "algorithms/common/triangle_mesh.hpp"

namespace bimslam::change_detection {

struct TruthChanges {
    struct Added {
        std::string name, kind;
        Eigen::AlignedBox3d box;
        common::TriangleMesh mesh;  // empty when the file named none
        long beam_hits = -1;        // beams of any scan on it; -1: the file does not say
    };
    struct Moved {
        std::string global_id, ifc_class, name, reason;  // reason: "moved" or "as_built"
        Eigen::Vector3d translation = Eigen::Vector3d::Zero();
        double yaw_deg = 0;
    };
    struct Person {
        Eigen::Vector2d from, to;
        double radius_m = 0, height_m = 0, floor_z = 0;
    };
    std::vector<Added> added;
    std::vector<std::string> removed;               // GlobalIds
    std::map<std::string, long> removed_beam_hits;  // by GlobalId, where the file says (any scan)
    std::vector<Moved> moved;
    std::vector<Person> people;
};
// Reads the meshes the file names (relative to its folder). Throws common::FileError naming the
// file and the field on a missing or malformed one.
TruthChanges ReadTruthChanges(const std::filesystem::path& file);

// What a run wrote (changes.json and elements.csv in `dir`).
struct FoundChanges {
    struct Object {
        Eigen::AlignedBox3d box;
        std::string ifc_global_id = {};  // the proxy's in model_updated.ifc ("" in older files)
        std::string storey = {};         // its storey's name ("" when none)
        int id = -1;                     // its id in changes.json (its mesh's part)
        double volume_m3 = 0;            // of its voxel solid (0 in older files)
        // Its smallest rectangle in plan, whatever its turn (long >= short; 0 in older files).
        double plan_long_m = 0, plan_short_m = 0;
        // That rectangle's centre (x, y; nullopt in older files).
        std::optional<Eigen::Vector2d> plan_center = std::nullopt;
    };
    struct Element {
        std::string verdict;
        double expected_area_m2 = 0;
        size_t support_points = 0;
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
        bool moved = false;
        double moved_yaw_deg = 0;
        // elements.csv's (storey: its name, "" when none; index: in the model's element list,
        // map_bim.ply's scalar_element).
        std::string ifc_class = {}, name = {}, storey = {};
        int index = -1;
    };
    std::vector<Object> objects;
    std::vector<Eigen::Vector3d> transients;  // centroids
    std::map<std::string, Element> elements;  // by GlobalId
    std::set<std::string> datum;              // GlobalIds of the surveyed elements
    // map_bim.ply: one point per map voxel, its unsigned distance to the model and how many
    // keyframes saw it; `has_map` false when the run wrote none.
    struct MapPoint {
        Eigen::Vector3f xyz;
        float model_distance_m = 0;
        uint32_t keyframes = 0;
        // scalar_class and scalar_element (change_report.hpp; 255 and -1 in files without them).
        uint8_t cls = 255;
        int32_t element = -1;
    };
    std::vector<MapPoint> map;
    bool has_map = false;
    // The detector's minimum, from changes.json's parameters (the defaults where a file lacks
    // them).
    size_t min_object_points = 30;
    double band_threshold_m = 0.05;
    double min_multi_view_fraction = 0.25;
    double min_judged_area_m2 = 0.25;
};
FoundChanges ReadFoundChanges(const std::filesystem::path& dir);

struct EvaluationConfig {
    double min_iou = 0.25;
    double max_centroid_m = 0.3;
    double large_object_m = 0.3;
    double large_area_m2 = 1.0;
    double person_margin_m = 0.3;
    size_t min_support_points = 30;
    double touch_m = 0.05;
    // A map point within this of a true object's surface (one map voxel) and nearer to it than to
    // the model is a point the keyframes put on it ("seen", above).
    double on_object_m = 0.05;
};

struct DetectionScores {
    size_t truth = 0, found = 0, truth_matched = 0, found_matched = 0;
    double precision() const { return found ? double(found_matched) / double(found) : 1.0; }
    double recall() const { return truth ? double(truth_matched) / double(truth) : 1.0; }
    double f1() const {
        const double p = precision(), r = recall();
        return p + r > 0 ? 2 * p * r / (p + r) : 0.0;
    }
};

struct ChangeEvaluation {
    DetectionScores added, added_large, added_separable, added_separable_large, removed,
        removed_large;
    size_t touching_groups = 0;  // groups of true objects that touch (more than one object)
    // Of what the walk saw (see the file comment): recall over the true objects in view; how
    // many were out of view, and of those how many no beam hit at all.
    DetectionScores added_seen, added_seen_large, removed_seen;
    size_t added_out_of_view = 0, added_large_out_of_view = 0, removed_out_of_view = 0;
    size_t added_no_beam = 0, added_large_no_beam = 0, removed_no_beam = 0;
    struct InViewRule {
        size_t min_points = 0;
        double min_multi_view_fraction = 0, on_object_m = 0, off_model_m = 0, min_area_m2 = 0;
    } in_view_rule;
    struct AddedView {
        std::string name;
        bool large = false, in_view = false, found = false;
        long beam_hits = -1;                           // any scan's (the truth's), -1 unknown
        size_t map_points = 0, multi_view_points = 0;  // the keyframes' map points on it
        Eigen::AlignedBox3d seen_box;                  // their box when in view, else empty
    };
    std::vector<AddedView> added_view;  // per true added object, in the truth's order
    struct RemovedView {
        std::string global_id;
        bool in_view = false, found = false;
        long beam_hits = -1;
        double expected_area_m2 = 0;  // the keyframes' beams on where it stood
    };
    std::vector<RemovedView> removed_view;
    struct MovedScore {
        std::string global_id;
        bool found = false;
        double translation_error_m = 0, yaw_error_deg = 0, true_translation_m = 0;
    };
    std::vector<MovedScore> moved;
    struct WallScore {
        std::string global_id;
        double true_offset_m = 0;      // signed along the true direction
        double measured_offset_m = 0;  // ours projected on it
        double error_m = 0;            // |ours - true| (vectors)
        std::string verdict;
    };
    std::vector<WallScore> walls;  // observed as-built walls
    size_t walls_unobserved = 0;
    size_t walls_datum = 0;  // surveyed (the refinement's datum), not scored
    size_t people = 0, people_as_objects = 0, people_with_transients = 0;

    nlohmann::json ToJson() const;
    nlohmann::json SeenJson() const;  // ToJson's "seen"
};

ChangeEvaluation EvaluateChanges(const TruthChanges& truth, const FoundChanges& found,
                                 const EvaluationConfig& config = {});

}  // namespace bimslam::change_detection
