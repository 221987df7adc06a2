// `bakegi web export`: a scene folder for the web page (issue 16, §4): scene.gltf +
// scene.bin (progressive meshes), grid.bgivg + grid_visibility.bin, and the page itself
// (index.html, viewer.js) from the client folder, so that `bakegi serve` or a browser opening
// the folder shows it.
#include <cstdio>
#include <filesystem>

#include "arguments.h"
#include "commands.h"
#include "core_handles.h"
#include "exit_codes.h"
#include "file_error.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

// Copies the page's files (every file of the client folder) into the scene folder.
size_t copy_client(const std::filesystem::path& client, const std::filesystem::path& folder) {
  size_t copied = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(client, error)) {
    if (!entry.is_regular_file()) continue;
    std::filesystem::copy_file(entry.path(), folder / entry.path().filename(),
                               std::filesystem::copy_options::overwrite_existing, error);
    if (error) throw FileError("copying the page: " + error.message());
    ++copied;
  }
  if (error) throw FileError(client.string() + ": " + error.message());
  return copied;
}

}  // namespace

int run_web_command(const std::vector<std::string>& words) {
  if (words.empty() || words[0] != "export") {
    throw UsageError("web expects 'export'");
  }
  const Arguments args({words.begin() + 1, words.end()},
                       {{"out"}, {"grid"}, {"camera"}, {"client"}});
  if (args.positional().size() != 1) throw UsageError("web export expects one scene file");
  const std::string out = args.require("out");
  const SceneFile file = load_scene_file(args.positional()[0]);
  GridHandle grid;
  if (const auto grid_path = args.value("grid")) {
    bakegi_grid* raw = nullptr;
    check(bakegi_grid_read_file(grid_path->c_str(), &raw), "reading " + *grid_path);
    grid = GridHandle(raw);
  }
  std::vector<float> camera;
  if (const auto text = args.value("camera")) {
    camera = parse_float_list(*text, "--camera (x,y,z, quaternion x,y,z,w, yfov, aspect)", 9);
  }
  check(bakegi_web_export(file.scene.get(), grid.get(), out.c_str(),
                          camera.empty() ? nullptr : camera.data()),
        "writing the web scene to " + out);
  size_t page_files = 0;
  if (const auto client = args.value("client")) page_files = copy_client(*client, out);
  // The visibility volume is left out for a grid past its budget (bakegi_web_export).
  const char* grid_files =
      !grid ? ""
      : std::filesystem::exists(std::filesystem::path(out) / "grid_visibility.bin")
          ? ", grid.bgivg, grid_visibility.bin"
          : ", grid.bgivg";
  std::fprintf(
      stderr, "wrote %s/scene.gltf, scene.bin%s%s\n", out.c_str(), grid_files,
      page_files ? (" and the page (" + std::to_string(page_files) + " files)").c_str() : "");
  return kExitOk;
}

}  // namespace bakegi::cli
