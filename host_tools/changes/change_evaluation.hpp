// `bimslam changes --truth`: a run's changes.json and elements.csv against the simulator's ground
// truth (a capture's changes.json, host_tools/simulate/world.hpp), the scores of issue 13:
//   added objects     precision, recall, F1; a found object matches a true one (one to one,
//                     best first) when their boxes' 3D IoU >= 0.25 or their centres are within
//                     0.3 m. "large": true objects of at least 0.3 m (largest extent) for recall,
//                     found objects of at least 0.3 m for precision (a small true object found
//                     counts for neither; one found large but not true counts against).
//                     "separable": the same with true objects whose surfaces come within
//                     touch_m (one map voxel, 5 cm) of each other taken as one (their union box):
//                     objects placed by hand may touch, and no 5 cm map separates them (the
//                     simulator's random clutter keeps 5 cm clear of other objects).
//                     Needs the truth's meshes (changes/*.ply beside its changes.json).
//   removed elements  recall and precision by GlobalId against the elements found missing; "large":
//                     those with at least 1 m^2 of expected visible surface (elements.csv).
//   moved elements    found (deviating with a fitted motion), the error of the translation and yaw.
//   as-built walls    the measured offset against the true one (vector difference), for the walls
//                     the session saw (support >= 30 points) and that were not surveyed (a wall
//                     in `parameters.refinement.datum` is measured to its survey: counted apart).
//   seen              (issue 31, item 8) the simulator writes how many beams hit each added
//                     object and removed element (`beam_hits`); one hit by fewer than
//                     min_seen_beam_hits over the whole walk was out of sight and cannot be found.
//                     The "seen" scores count only the others in recall (precision is the same:
//                     a found object that matches an unseen true one is no false alarm) and say
//                     how many were out of sight. Truth files without beam_hits: every object seen.
//   people            found objects that match no added object and lie in a person's path (its
//                     line widened by radius + 0.3 m, from its floor to its height): should be
//                     none; people with a transient cluster on their line.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
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
        long beam_hits = -1;        // beams on it over the walk; -1: the file does not say
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
    std::map<std::string, long> removed_beam_hits;  // by GlobalId, where the file says
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
    };
    struct Element {
        std::string verdict;
        double expected_area_m2 = 0;
        size_t support_points = 0;
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
        bool moved = false;
        double moved_yaw_deg = 0;
    };
    std::vector<Object> objects;
    std::vector<Eigen::Vector3d> transients;  // centroids
    std::map<std::string, Element> elements;  // by GlobalId
    std::set<std::string> datum;              // GlobalIds of the surveyed elements
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
    // Fewer beam hits than this over the whole walk: out of sight (a DBSCAN core point needs 8
    // points within one 5 cm voxel's reach; 20 scattered hits make no cluster).
    long min_seen_beam_hits = 20;
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
    // Of what the walk saw (see the file comment): recall over the seen true objects; and how
    // many were out of sight.
    DetectionScores added_seen, added_seen_large, removed_seen;
    size_t added_out_of_sight = 0, added_large_out_of_sight = 0, removed_out_of_sight = 0;
    long min_seen_beam_hits = 0;  // the config's: fewer beam hits than this were out of sight
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
};

ChangeEvaluation EvaluateChanges(const TruthChanges& truth, const FoundChanges& found,
                                 const EvaluationConfig& config = {});

}  // namespace bimslam::change_detection
