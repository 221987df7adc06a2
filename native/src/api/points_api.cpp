// bakegi_points_*: bake points enter the core here, checked and with unit normals.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "api/api_guard.h"
#include "api/handles.h"
#include "lightmap/backface_rejection.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

bool finite(const float* v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
const char* non_finite_word(const float* v) {
  return std::isnan(v[0]) || std::isnan(v[1]) || std::isnan(v[2]) ? "NaN" : "infinite";
}

}  // namespace

extern "C" {

bakegi_status bakegi_points_create(const float* positions, const float* normals,
                                   const uint32_t* object_ids, uint64_t count,
                                   bakegi_points** out_points) {
  return guarded(__func__, [&] {
    require(out_points, "out_points");
    *out_points = nullptr;
    require(positions, "positions");
    require(normals, "normals");
    if (count == 0) throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "count is 0 (no bake points)");
    // Keeps 3 * count * sizeof(float) and every later size computation from overflowing.
    if (count > std::numeric_limits<uint64_t>::max() / 64) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "count " + std::to_string(count) + " is absurd");
    }
    auto handle = std::make_unique<bakegi_points>();
    bakegi::BakePoints& points = handle->points;
    points.positions.resize(count);
    points.normals.resize(count);
    points.object_ids.assign(count, 0);
    for (uint64_t i = 0; i < count; ++i) {
      const float* p = positions + 3 * i;
      const float* n = normals + 3 * i;
      const std::string name = "bake point " + std::to_string(i);
      if (!finite(p)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": position is " + non_finite_word(p));
      }
      if (!bakegi::position_in_range({p[0], p[1], p[2]})) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    name + ": " + bakegi::position_out_of_range_text({p[0], p[1], p[2]}));
      }
      if (!finite(n)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": normal is " + non_finite_word(n));
      }
      const glm::dvec3 normal(n[0], n[1], n[2]);
      const double length = glm::length(normal);
      if (!(length > 1e-20)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": normal is the zero vector");
      }
      points.positions[i] = {p[0], p[1], p[2]};
      points.normals[i] = glm::vec3(normal / length);
      if (object_ids) points.object_ids[i] = object_ids[i];
    }
    *out_points = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_points_set_display_probes(bakegi_points* points, const float* positions,
                                               const float* normals, const uint32_t* object_ids,
                                               const uint32_t* indices, const float* weights,
                                               uint64_t count) {
  return guarded(__func__, [&] {
    require(points, "points");
    if (count > 0) {
      require(positions, "positions");
      require(normals, "normals");
      require(indices, "indices");
      require(weights, "weights");
    }
    if (count > (uint64_t(1) << 32)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "count " + std::to_string(count) + " is absurd");
    }
    bakegi::ErrorProbes probes;
    for (uint64_t i = 0; i < count; ++i) {
      const float* p = positions + 3 * i;
      const float* n = normals + 3 * i;
      probes.add({p[0], p[1], p[2]}, {n[0], n[1], n[2]}, object_ids ? object_ids[i] : 0,
                 {indices[4 * i], indices[4 * i + 1], indices[4 * i + 2], indices[4 * i + 3]},
                 {weights[4 * i], weights[4 * i + 1], weights[4 * i + 2], weights[4 * i + 3]});
    }
    bakegi::check_error_probes(probes, points->points.size());
    points->display_probes = std::move(probes);
  });
}

bakegi_status bakegi_points_set_share_candidates(bakegi_points* points, const uint32_t* candidates,
                                                 uint64_t count) {
  return guarded(__func__, [&] {
    require(points, "points");
    if (count > 0) require(candidates, "candidates");
    if (count != points->points.size()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "count " + std::to_string(count) + " differs from the " +
                      std::to_string(points->points.size()) + " bake points");
    }
    std::vector<uint32_t> given(candidates, candidates + count);
    bakegi::check_share_candidates(given, given.size());
    points->points.share_candidates = std::move(given);
  });
}

void bakegi_points_destroy(bakegi_points* points) {
  bakegi::destroy_handle(points);
}

uint64_t bakegi_points_count(const bakegi_points* points) {
  return bakegi::live(points) ? points->points.size() : 0;
}

bakegi_status bakegi_points_get(const bakegi_points* points, float* positions, float* normals,
                                uint32_t* object_ids) {
  return guarded(__func__, [&] {
    require(points, "points");
    const bakegi::BakePoints& p = points->points;
    for (size_t i = 0; i < p.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        if (positions) positions[3 * i + k] = p.positions[i][k];
        if (normals) normals[3 * i + k] = p.normals[i][k];
      }
      if (object_ids) object_ids[i] = p.object_ids[i];
    }
  });
}

bakegi_status bakegi_points_flag_inside(const bakegi_points* points, const bakegi_scene* scene,
                                        uint32_t rays, float backface_fraction, float max_distance,
                                        uint8_t* out_flags) {
  return guarded(__func__, [&] {
    require(points, "points");
    require(scene, "scene");
    const bakegi::BakePoints& p = points->points;
    if (p.size() > 0) require(out_flags, "out_flags");
    bakegi::BackfaceRejectionOptions options;
    if (rays != 0) options.rays = rays;
    if (backface_fraction != 0) options.backface_fraction = backface_fraction;
    options.max_distance = max_distance;
    if (p.size() == 0) return;
    const bakegi::Scene built = bakegi::build_scene(scene->description);
    const bakegi::RayTracer tracer(built);
    // Bake points carry one normal: it stands for the surface's side too.
    const std::vector<uint8_t> flags = bakegi::flag_samples_inside_geometry(
        built, tracer, p.positions, p.normals, p.normals, options);
    std::copy(flags.begin(), flags.end(), out_flags);
  });
}

}  // extern "C"
