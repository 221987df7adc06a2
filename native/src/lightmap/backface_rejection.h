// Lightmap samples that lie inside or under other geometry. Conservative rasterization puts
// samples of edge texels where a wall meets the floor or where an object stands in (or on)
// a surface; such a sample is inside the other object's solid and would show light from the
// far side (a leak) or black. Like mature lightmappers (Unity's "backface tolerance",
// Bakery's texel validity), a sample is judged by what it sees: from inside a solid, the
// rays of its hemisphere meet back faces; from open space, front faces or nothing. Flagged
// samples are dropped and their texels filled from their neighbours (lightmap_padding.h).
//
// Judged with `rays` fixed, stratified cosine-distributed directions around the sample's
// geometric normal (turned to its shading normal's side); the result is deterministic.
// A one-sided plane seen from behind over a large part of a sample's hemisphere also counts
// as "inside": that is what the fraction threshold trades off.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/cancel_flag.h"

namespace bakegi {

struct BackfaceRejectionOptions {
  uint32_t rays = 32;  // per sample, >= 1
  // A sample is flagged when at least this fraction of its rays hit back faces, (0, 1].
  // Unity's default backface tolerance (90% front hits required) is 0.1; 0.25 leaves a
  // sample beside a one-sided plane's back alone unless the plane fills a quarter of its view.
  float backface_fraction = 0.25f;
  // Only hits closer than this (metres) count; 0 = any distance.
  float max_distance = 0.0f;
};

// One flag per sample (1 = inside or under geometry). positions, geometric normals and
// shading normals have one entry per sample. Throws Error(INVALID_ARGUMENT) for bad options,
// Error(CANCELLED) when `cancel` is raised (checked every 64 samples).
std::vector<uint8_t> flag_samples_inside_geometry(const Scene& scene, const RayTracer& tracer,
                                                  const std::vector<glm::vec3>& positions,
                                                  const std::vector<glm::vec3>& geometric_normals,
                                                  const std::vector<glm::vec3>& shading_normals,
                                                  const BackfaceRejectionOptions& options = {},
                                                  const CancelFlag* cancel = nullptr);

}  // namespace bakegi
