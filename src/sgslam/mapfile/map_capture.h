// Between a live map and its saved form (map_data.h): CaptureMap copies the map
// (and the semantic layer) into plain data, RestoreMap builds an empty Map up from
// it. Culled keyframes are saved (without features) only when the semantic layer or
// the spanning tree is anchored to them.
#pragma once

#include <memory>
#include <string>

#include "sgslam/camera/camera.h"
#include "sgslam/map/map.h"
#include "sgslam/mapfile/map_data.h"
#include "sgslam/semantic/semantic_mapper.h"

namespace sgslam::mapfile {

// Takes the map's shared lock while it copies the map's structure; the keyframes'
// features (immutable once in the map) are copied after. Keyframes local mapping has
// not inserted yet are left out, with their observations. semantic: the semantic
// mapper's state, or null without the semantic thread. next_frame_id: the system's
// next frame id.
MapData CaptureMap(const Map& map, const Settings& settings, std::uint64_t next_frame_id,
                   const SemanticState* semantic);

// The settings a run uses, for the checks below.
Settings RunSettings(const CameraConfig& camera, double orb_scale_factor, int orb_levels,
                     const std::string& vocabulary_checksum);

// Throws InputError naming `what` when the map was made with another camera
// (intrinsics, distortion, image size, depth factor), other ORB pyramid settings,
// or another vocabulary than the run's.
void CheckCompatible(const Settings& saved, const Settings& run, const std::string& what);

// Fills map (empty; nothing else may use it yet) with data's keyframes and points,
// whose features use camera and scale; returns the semantic state on the restored
// keyframes (empty clouds and objects when the map has none).
SemanticState RestoreMap(const MapData& data, Map& map, const std::shared_ptr<const Camera>& camera,
                         const std::shared_ptr<const ScaleLevels>& scale);

}  // namespace sgslam::mapfile
