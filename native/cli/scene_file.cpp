#include "scene_file.h"

namespace bakegi::cli {

SceneFile load_scene_file(const std::string& path) {
  bakegi_scene* scene = nullptr;
  bakegi_points* points = nullptr;
  check(bakegi_file_read(path.c_str(), &scene, &points), "reading " + path);
  return SceneFile{SceneHandle(scene), PointsHandle(points)};
}

SceneFile load_scene_file_with_points(const std::string& path) {
  SceneFile file = load_scene_file(path);
  if (!file.points || bakegi_points_count(file.points.get()) == 0) {
    throw CoreError(BAKEGI_ERROR_BAD_FILE,
                    path +
                        " holds no bake points; export it with bake points "
                        "(bakegi.export_scene_file(path, target=...)) to bake it");
  }
  return file;
}

}  // namespace bakegi::cli
