// bakegi_preview_*: the splatting method's interactive preview (issue 17, item 5).
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <variant>

#include <glm/gtc/quaternion.hpp>

#include "api/api_guard.h"
#include "api/handles.h"
#include "api/text_output.h"
#include "solvers/method_registry.h"
#include "solvers/splatting/splatting_preview.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

struct bakegi_preview {
  std::unique_ptr<bakegi::SplattingPreview> preview;
  std::string report = "{}";
};

namespace {

// Beyond this many pixels the G-buffer and the buffers (about 150 bytes a pixel) would pass
// a few GB: a preview never needs it.
constexpr uint64_t kMaxPreviewPixels = uint64_t(8192) * 8192;

bakegi::PreviewCamera camera_from(const float* c) {
  require(c, "camera");
  for (int i = 0; i < 12; ++i) {
    if (!std::isfinite(c[i]))
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "camera values must be finite");
  }
  const glm::quat q(c[6], c[3], c[4], c[5]);  // glm: w first
  if (!(glm::length(q) > 1e-6f)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "camera: the rotation quaternion is zero");
  }
  const glm::quat r = glm::normalize(q);
  bakegi::PreviewCamera camera;
  camera.position = {c[0], c[1], c[2]};
  camera.forward = r * glm::vec3(0.0f, 0.0f, -1.0f);
  camera.up = r * glm::vec3(0.0f, 1.0f, 0.0f);
  camera.fov_y = c[7];
  camera.shift_x = c[8];
  camera.shift_y = c[9];
  camera.ortho_scale = c[10];
  if (!(camera.ortho_scale >= 0.0f)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "camera: the orthographic scale is negative");
  }
  if (camera.ortho_scale == 0.0f && !(camera.fov_y > 1e-4f && camera.fov_y < 3.1f)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "camera: the vertical field of view must lie in (0, pi) radians");
  }
  return camera;
}

std::string report_json(const bakegi::PreviewFrame& frame) {
  const bakegi::PreviewStatistics& s = frame.statistics;
  std::ostringstream o;
  o << "{\"width\": " << frame.width << ", \"height\": " << frame.height << ", \"vpls\": " << s.vpls
    << ", \"rsm_texels\": " << s.rsm_texels
    << ", \"gbuffer_reused\": " << (s.gbuffer_reused ? "true" : "false")
    << ", \"glossy_pixels\": " << s.glossy_pixels << ", \"subsplats\": " << s.splat.subsplats
    << ", \"subsplats_per_level\": [";
  for (size_t k = 0; k < s.splat.subsplats_per_level.size(); ++k) {
    o << (k ? ", " : "") << s.splat.subsplats_per_level[k];
  }
  o << "], \"coarsest_level\": " << s.splat.coarsest_level
    << ", \"finest_level\": " << s.splat.finest_level
    << ", \"seconds\": {\"gbuffer\": " << s.seconds_gbuffer << ", \"direct\": " << s.seconds_direct
    << ", \"rsm\": " << s.seconds_rsm << ", \"vpls\": " << s.seconds_vpls
    << ", \"mipmap\": " << s.splat.seconds_mipmap << ", \"refine\": " << s.splat.seconds_refine
    << ", \"render\": " << s.splat.seconds_render << ", \"upsample\": " << s.splat.seconds_upsample
    << ", \"glossy\": " << s.seconds_glossy << ", \"total\": " << s.seconds_total << "}}";
  return o.str();
}

}  // namespace

extern "C" {

bakegi_status bakegi_preview_create(const bakegi_scene* scene, bakegi_preview** out_preview) {
  return guarded(__func__, [&] {
    require(out_preview, "out_preview");
    *out_preview = nullptr;
    require(scene, "scene");
    auto handle = std::make_unique<bakegi_preview>();
    handle->preview = std::make_unique<bakegi::SplattingPreview>(scene->description);
    *out_preview = bakegi::give_out(std::move(handle));
  });
}

void bakegi_preview_destroy(bakegi_preview* preview) {
  bakegi::destroy_handle(preview);
}

bakegi_status bakegi_preview_set_lights(bakegi_preview* preview, const bakegi_scene* lights) {
  return guarded(__func__, [&] {
    require(preview, "preview");
    require(lights, "lights");
    preview->preview->set_lights(lights->description.lights, lights->description.world_radiance);
  });
}

bakegi_status bakegi_preview_render(bakegi_preview* preview, const float* camera, uint32_t width,
                                    uint32_t height, const bakegi_settings* settings,
                                    float* out_rgba, float* out_direct, float* out_indirect,
                                    uint8_t* out_levels) {
  return guarded(__func__, [&] {
    require(preview, "preview");
    const bakegi::PreviewCamera view = camera_from(camera);
    if (width == 0 || height == 0 || uint64_t(width) * height > kMaxPreviewPixels) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "the image must have between 1 and 8192 x 8192 pixels");
    }
    bakegi::Settings given = settings ? settings->settings : bakegi::Settings();
    given.validate(bakegi::method_schema("splatting"), bakegi::setting_keys_of_any_method());
    // The method's defaults are the bake's; a frame takes the paper's (docs/methods/
    // splatting.md) unless asked: 256 VPLs, a 16-texel coarsest level, no visibility rays,
    // and no near-field split (5-15x a frame on rooms: every VPL near a wall is near some
    // pixel).
    if (!given.has("vpl_count")) given.set("vpl_count", int64_t(256));
    if (!given.has("base_resolution")) given.set("base_resolution", int64_t(16));
    if (!given.has("visibility_clusters")) given.set("visibility_clusters", int64_t(0));
    if (!given.has("near_field_split")) given.set("near_field_split", 0.0);
    // And the refinement measured best for frames on six scenes (docs/methods/splatting.md):
    // the curvature normal test at 0.1 (about 6 degrees between neighbouring pixels) and no
    // neighbour rule; the component test and diagonal rule refine up to twice as much for
    // the same error.
    if (!given.has("normal_test")) given.set("normal_test", std::string("curvature"));
    const auto* test = std::get_if<std::string>(&given.values().at("normal_test"));
    if (!given.has("normal_threshold") && test && *test == "curvature") {
      given.set("normal_threshold", 0.1);
    }
    if (!given.has("refine_neighbours")) given.set("refine_neighbours", std::string("none"));
    bakegi::SplattingSettings parsed = bakegi::SplattingSettings::from(given);
    parsed.record_pixel_levels = out_levels != nullptr;
    const bakegi::PreviewFrame& frame = preview->preview->render(view, width, height, parsed);
    const size_t n = size_t(width) * height;
    for (size_t i = 0; i < n; ++i) {
      if (out_rgba) {
        for (int c = 0; c < 3; ++c) out_rgba[4 * i + c] = frame.combined[i][c];
        out_rgba[4 * i + 3] = frame.seen[i] ? 1.0f : 0.0f;
      }
      for (int c = 0; c < 3; ++c) {
        if (out_direct) out_direct[3 * i + c] = frame.direct[i][c];
        if (out_indirect) out_indirect[3 * i + c] = frame.indirect[i][c];
      }
    }
    if (out_levels) {
      const std::vector<uint8_t>& levels = frame.statistics.splat.pixel_levels;
      for (size_t i = 0; i < n; ++i) out_levels[i] = levels.empty() ? 255 : levels[i];
    }
    preview->report = report_json(frame);
  });
}

bakegi_status bakegi_preview_get_report(const bakegi_preview* preview, char* buffer,
                                        size_t capacity, size_t* out_length) {
  return guarded(__func__, [&] {
    require(preview, "preview");
    bakegi::check_text_output(buffer, capacity, out_length);
    bakegi::write_text_output(preview->report, buffer, capacity, out_length);
  });
}

}  // extern "C"
