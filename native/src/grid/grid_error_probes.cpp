#include "grid/grid_error_probes.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "scene/scene.h"
#include "util/pcg32.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

ErrorProbes grid_surface_probes(const Scene& scene, const GridLayout& layout, size_t count,
                                uint64_t seed) {
  ErrorProbes probes;
  std::vector<double> cumulative_area;
  cumulative_area.reserve(scene.triangles.size());
  double total = 0.0;
  for (const Triangle& t : scene.triangles) cumulative_area.push_back(total += t.area);
  if (count == 0 || !(total > 0.0)) return probes;
  Pcg32 rng = sample_pcg(seed, 0x6772696450726F62ull /* "gridProb" */, 0);
  for (size_t draw = 0; draw < 32 * count && probes.size() < count; ++draw) {
    const double pick = double(unit_float(rng.next_uint())) * total;
    const size_t index =
        std::min(size_t(std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                        cumulative_area.begin()),
                 scene.triangles.size() - 1);
    const Triangle& t = scene.triangles[index];
    const glm::vec2 b =
        sample_triangle_barycentrics(unit_float(rng.next_uint()), unit_float(rng.next_uint()));
    const float b0 = 1.0f - b.x - b.y;
    const glm::vec3 p = b0 * t.p[0] + b.x * t.p[1] + b.y * t.p[2];
    if (glm::any(glm::lessThan(p, layout.bounds_min)) ||
        glm::any(glm::greaterThan(p, layout.bounds_max))) {
      continue;
    }
    glm::vec3 n = b0 * t.n[0] + b.x * t.n[1] + b.y * t.n[2];
    const float length = glm::length(n);
    n = length > 0.0f ? n / length : t.face_normal;
    const uint32_t i = uint32_t(probes.size());
    probes.add(p, n, scene.description.meshes[t.mesh].object_id, {i, i, i, i},
               {1.0f, 0.0f, 0.0f, 0.0f});
  }
  return probes;
}

}  // namespace bakegi
