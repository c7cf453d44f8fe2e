// Scores a run's mover tracks (tracks.txt, movers/tracks_file.h) against the true
// movers of its sequence, when it knows them:
//   movers.txt (sgslam synth): per frame, each visible mover's pixels and the mean
//     world point of its visible surface;
//   dynamic_objects.txt (the composite generator, e.g. dyn_dev): each mover's world
//     position and size (its orientations are not usable: dyn_dev's are all the
//     same); the visible part is computed here: every moving pixel of the frame's
//     mask is lifted with its depth (the mover's: the mask marks where it is nearer
//     than the scene) from the true camera (pinhole: the generator draws the
//     movers without lens distortion) and given to the mover whose vertical axis is
//     nearest within its reach (a person's half width, a box's half diagonal, plus
//     0.15 m); the mean of a mover's points is the centre of its visible part.
// The track centroids are brought into the truth's world with the ATE alignment of
// the run's trajectory, then matched per frame to the visible movers (confirmed
// tracks only, within match_gate): as CLEAR MOT does, a mover keeps the track that
// covered it last while it stays within the gate, the rest go nearest pair first.
// An id switch is a change of the covering track.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sgslam/camera/camera_config.h"
#include "sgslam/common/time.h"
#include "sgslam/io/trajectory.h"
#include "sgslam/movers/tracks_file.h"

namespace sgslam::eval {

struct TrueMover {
  int id = 0;
  std::string class_name;
  int pixels = 0;                                      // visible pixels
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // m, world: centre of the visible part
};

struct MoverTruth {
  std::string source;                               // the file it came from
  int image_pixels = 0;                             // width * height
  std::map<Timestamp, std::vector<TrueMover>> frames;  // the frames with a visible mover... and without (empty)
};

// The truth of the sequence in dir (movers.txt first, else dynamic_objects.txt with
// mask.txt and groundtruth.txt); nullopt when it has neither. Throws InputError /
// ParseError naming the file for a malformed one.
std::optional<MoverTruth> LoadMoverTruth(const std::filesystem::path& dir, const CameraConfig& camera);

struct TrackScoreOptions {
  double match_gate = 0.5;       // m, a confirmed track this near a mover's visible centre covers it
  double min_visible = 0.10;     // share of the image a mover must cover for the coverage target
};

struct MoverScore {
  int id = 0;
  std::string class_name;
  int frames_visible = 0;  // frames it covers at least min_visible of the image
  int frames_covered = 0;  // of those, frames a confirmed track covers it
  int id_switches = 0;     // changes of the covering track over the run
};

struct TrackScore {
  int frames = 0;  // frames of the run with a pose (tracks.txt's frames)
  std::vector<MoverScore> movers;
  int false_tracks = 0;               // confirmed tracks that cover no mover in most of their confirmed frames
  double false_per_100_frames = 0;
  double coverage = 0;                // frames_covered / frames_visible over all movers
  double min_coverage = 0;            // the worst mover's
  int max_id_switches = 0;
  double median_centroid_error = 0;   // m, over every covering match (all visible sizes)
  int matches = 0;
};

// est: the run's trajectory.txt, gt: the sequence's groundtruth.txt (the alignment).
TrackScore ScoreTracks(const MoverTruth& truth, const std::vector<movers::TrackLine>& tracks, const Trajectory& est,
                       const Trajectory& gt, const TrackScoreOptions& options = {});

nlohmann::json ToJson(const TrackScore& score, const TrackScoreOptions& options = {});

}  // namespace sgslam::eval
