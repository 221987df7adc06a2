// bakegi info scene.bgs: what a scene file holds, whether the core accepts it, and the
// library version.
#include <cstdio>

#include "arguments.h"
#include "commands.h"
#include "exit_codes.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

int run_info_command(const std::vector<std::string>& words) {
  const Arguments args(words, {});
  if (args.positional().size() != 1) throw UsageError("info expects one scene file");
  const std::string path = args.positional()[0];
  const SceneFile file = load_scene_file(path);

  std::printf("file:       %s\n", path.c_str());
  std::printf("triangles:  %llu\n",
              static_cast<unsigned long long>(bakegi_scene_triangle_count(file.scene.get())));
  std::printf("lights:     %u\n", bakegi_scene_light_count(file.scene.get()));
  std::printf("portals:    %u\n", bakegi_scene_portal_count(file.scene.get()));
  std::printf("points:     %llu\n", static_cast<unsigned long long>(
                                        file.points ? bakegi_points_count(file.points.get()) : 0));
  const bakegi_status status = bakegi_scene_validate(file.scene.get());
  if (status == BAKEGI_OK) {
    std::printf("valid:      yes\n");
  } else {
    std::printf("valid:      no: %s (%s)\n", bakegi_last_error(), bakegi_status_string(status));
  }
  std::printf("library:    bakegi %s\n", bakegi_version_string());
  return status == BAKEGI_OK ? kExitOk : kExitBakeFailed;
}

}  // namespace bakegi::cli
