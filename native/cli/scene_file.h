// A .bgs scene file loaded through the C API: the scene and its bake points.
#pragma once

#include <string>

#include "core_handles.h"

namespace bakegi::cli {

struct SceneFile {
  SceneHandle scene;
  PointsHandle points;  // null if the file holds none
};

// Throws CoreError (BAKEGI_ERROR_IO / BAD_FILE ...) naming the path.
SceneFile load_scene_file(const std::string& path);
// As load_scene_file, but a file without bake points is an error (bake and sweep need them).
SceneFile load_scene_file_with_points(const std::string& path);

}  // namespace bakegi::cli
