// `bakegi preview scene.bgs --camera ... --out image.npy`: one frame of the splatting method's
// preview (issue 17): direct light plus one bounce splatted through the adaptive
// multiresolution buffer, as the render engine "BakeGI Preview" shows it. --repeat renders
// the frame again with the same camera (the G-buffer is kept, as when only lights move) and
// prints each frame's report, so the per-step timings of an interactive update are visible.
#include <cstdio>
#include <string>

#include "arguments.h"
#include "bake_settings.h"
#include "commands.h"
#include "core_handles.h"
#include "exit_codes.h"
#include "npy_file.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

std::string preview_report(const bakegi_preview* preview) {
  size_t length = 0;
  check(bakegi_preview_get_report(preview, nullptr, 0, &length), "reading the report");
  std::string text(length + 1, '\0');
  check(bakegi_preview_get_report(preview, text.data(), text.size(), nullptr),
        "reading the report");
  text.resize(length);
  return text;
}

}  // namespace

int run_preview_command(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  for (const char* name :
       {"camera", "width", "height", "out", "direct", "indirect", "levels", "repeat"}) {
    specs.push_back({name});
  }
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("preview expects one scene file");
  const std::vector<float> camera = parse_float_list(
      args.require("camera"),
      "--camera (x,y,z, quaternion x,y,z,w, yfov, shift x, shift y, ortho scale, 0)", 12);
  const uint32_t width = uint32_t(args.int_value("width", 640, 1, 8192));
  const uint32_t height = uint32_t(args.int_value("height", 480, 1, 8192));
  const int repeat = int(args.int_value("repeat", 1, 1, 1000));
  BakeSettings settings = bake_settings_from(args);
  if (!args.has("method")) settings.set("method", std::string("splatting"));
  if (settings.method() != "splatting") throw UsageError("preview renders method splatting only");
  const SettingsHandle core_settings = settings.to_core();

  const SceneFile file = load_scene_file(args.positional()[0]);
  bakegi_preview* raw = nullptr;
  check(bakegi_preview_create(file.scene.get(), &raw), "building the preview");
  const PreviewHandle preview(raw);
  check(bakegi_preview_set_lights(preview.get(), file.scene.get()), "setting the lights");

  const size_t n = size_t(width) * height;
  std::vector<float> rgba(4 * n), direct(3 * n), indirect(3 * n);
  std::vector<uint8_t> levels(n);
  for (int r = 0; r < repeat; ++r) {
    check(bakegi_preview_render(preview.get(), camera.data(), width, height, core_settings.get(),
                                rgba.data(), direct.data(), indirect.data(), levels.data()),
          "rendering the preview");
    std::printf("%s\n", preview_report(preview.get()).c_str());
  }
  if (const auto path = args.value("out"))
    write_npy_float32(*path, rgba.data(), {height, width, 4});
  if (const auto path = args.value("direct"))
    write_npy_float32(*path, direct.data(), {height, width, 3});
  if (const auto path = args.value("levels")) {
    const std::vector<float> as_float(levels.begin(), levels.end());
    write_npy_float32(*path, as_float.data(), {height, width});
  }
  if (const auto path = args.value("indirect"))
    write_npy_float32(*path, indirect.data(), {height, width, 3});
  return kExitOk;
}

}  // namespace bakegi::cli
