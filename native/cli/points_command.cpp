// bakegi points scene.bgs [--positions p.npy] [--normals n.npy] [--object-ids ids.npy]:
// writes the file's bake points as float32 arrays ((n, 3), and (n,) for the object ids,
// exact below 2^24), so that scripts can check that another renderer's values come in the
// same order and group points by object (tools/sweep_cornell.py does both).
#include <cstdio>

#include "arguments.h"
#include "commands.h"
#include "exit_codes.h"
#include "npy_file.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

int run_points_command(const std::vector<std::string>& words) {
  const Arguments args(words, {{"positions"}, {"normals"}, {"object-ids"}});
  if (args.positional().size() != 1) throw UsageError("points expects one scene file");
  if (!args.has("positions") && !args.has("normals") && !args.has("object-ids")) {
    throw UsageError("points needs --positions, --normals and/or --object-ids");
  }
  const SceneFile file = load_scene_file_with_points(args.positional()[0]);
  const uint64_t count = bakegi_points_count(file.points.get());
  std::vector<float> positions(3 * count), normals(3 * count);
  std::vector<uint32_t> ids(count);
  check(bakegi_points_get(file.points.get(), positions.data(), normals.data(), ids.data()),
        "reading the bake points");
  if (const auto path = args.value("positions"))
    write_npy_float32(*path, positions.data(), {count, 3});
  if (const auto path = args.value("normals")) write_npy_float32(*path, normals.data(), {count, 3});
  if (const auto path = args.value("object-ids")) {
    const std::vector<float> ids_float(ids.begin(), ids.end());
    write_npy_float32(*path, ids_float.data(), {count});
  }
  std::fprintf(stderr, "wrote %llu bake points\n", static_cast<unsigned long long>(count));
  return kExitOk;
}

}  // namespace bakegi::cli
