#include "semantic_output.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "sgslam/io/atomic_write.h"
#include "sgslam/semantic/object_json.h"

namespace sgslam::app {

void WriteObjectsJson(const std::filesystem::path& path, const std::vector<ObjectEstimate>& objects,
                      bool candidates) {
  nlohmann::json doc = {
      {"map_frame",
       "the camera frame of the first keyframe: x right, y down, z forward, metres (as trajectory.txt); "
       "size is the axis-aligned extent in this frame, centroid the centre of that box; dimensions the extents "
       "along the object's principal axes, longest first; complete false: every view of the object was cut by "
       "the image border, the box covers the part seen"},
      {"objects", ObjectsJson(objects)}};
  // Kept apart: not confirmed yet, or of a size their class cannot have.
  if (candidates) doc["candidates"] = ObjectsJson(objects, true);
  WriteFileAtomically(path, doc.dump(2) + "\n");
}

void PrintObjectTable(const std::vector<ObjectEstimate>& objects) {
  int n = 0;
  for (const ObjectEstimate& o : objects) n += o.exported ? 1 : 0;
  std::printf("%d semantic objects%s\n", n, n > 0 ? ":" : "");
  if (n == 0) return;
  std::printf("  %4s  %-14s %5s %5s %5s  %-26s %s\n", "id", "class", "share", "conf", "obs", "centroid [m]",
              "size [m]");
  for (const ObjectEstimate& o : objects) {
    if (!o.exported) continue;
    std::printf("  %4d  %-14s %5.2f %5.2f %5d  %7.2f %7.2f %7.2f    %5.2f %5.2f %5.2f%s\n", o.id,
                o.class_name.c_str(), o.class_share, o.confidence, o.observations, o.centroid.x(), o.centroid.y(), o.centroid.z(), o.size.x(), o.size.y(),
                o.size.z(), o.complete ? "" : "  (partial: never seen whole)");
  }
}

}  // namespace sgslam::app
