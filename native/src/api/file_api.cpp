// bakegi_file_*: scene files through scene/scene_file.
#include "api/api_guard.h"
#include "api/handles.h"
#include "scene/scene_file.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

extern "C" {

bakegi_status bakegi_file_write(const char* path, const bakegi_scene* scene,
                                const bakegi_points* points) {
  return guarded(__func__, [&] {
    require(path, "path");
    require(scene, "scene");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    bakegi::write_scene_file(path, scene->description, points ? &points->points : nullptr);
  });
}

bakegi_status bakegi_file_read(const char* path, bakegi_scene** out_scene,
                               bakegi_points** out_points) {
  return guarded(__func__, [&] {
    require(out_scene, "out_scene");
    *out_scene = nullptr;
    if (out_points) *out_points = nullptr;
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    bakegi::SceneFile file = bakegi::read_scene_file(path);
    auto scene = std::make_unique<bakegi_scene>();
    scene->description = std::move(file.scene);
    std::unique_ptr<bakegi_points> points;
    if (out_points && file.points) {
      points = std::make_unique<bakegi_points>();
      points->points = std::move(*file.points);
    }
    *out_scene = bakegi::give_out(std::move(scene));
    if (out_points) *out_points = bakegi::give_out(std::move(points));
  });
}

}  // extern "C"
