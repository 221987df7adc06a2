// The Irradiance Vector Grid (Pacanowski et al. 2008, §3.1): at each grid vertex six
// irradiance vectors I_delta = integral over the hemisphere around delta of L(w) w dw
// (Arvo 1994), delta = +x, -x, +y, -y, +z, -z, one per colour channel: a 3x3 matrix per
// hemisphere (§3.3), column c the vector of channel c (R, G, B).
//
// Units: L is the radiance surfaces reflect (emission seen directly and lamps are direct light,
// as in every bake), so I_delta . n = the indirect irradiance E_indirect of a receiver with
// normal n = delta, and the baked value (the output convention) is I_n . n / pi
// (grid_interpolation.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "grid/grid_layout.h"

namespace bakegi {

inline constexpr int kGridHemispheres = 6;

// Hemisphere h is centred on axis h / 2 with sign + for even h: +x, -x, +y, -y, +z, -z.
inline glm::vec3 hemisphere_axis(int h) {
  glm::vec3 axis(0.0f);
  axis[h / 2] = (h % 2 == 0) ? 1.0f : -1.0f;
  return axis;
}

struct IrradianceVectorGrid {
  GridLayout layout;
  // vectors[vertex * 6 + h]: hemisphere h's matrix at the vertex (vertex_index order).
  std::vector<glm::mat3> vectors;
  // 1 where the vertex was gathered (or received); 0 inside geometry (or not yet streamed):
  // push-pull (grid_push_pull.h) fills those from valid neighbours.
  std::vector<uint8_t> valid;
  // The light that arrives straight from the world (sky) and from emissive surfaces, in the
  // same layout as `vectors`; empty when the scene has neither. Bakes leave it out (it is
  // direct light); the web page, which draws only lamps directly, adds it (web_api.cpp).
  std::vector<glm::mat3> emitted;

  explicit IrradianceVectorGrid(const GridLayout& l = {})
      : layout(l),
        vectors(l.vertex_count() * kGridHemispheres, glm::mat3(0.0f)),
        valid(l.vertex_count(), 0) {}

  size_t vertex_count() const { return layout.vertex_count(); }
  const glm::mat3& at(size_t vertex, int h) const { return vectors[vertex * kGridHemispheres + h]; }
  glm::mat3& at(size_t vertex, int h) { return vectors[vertex * kGridHemispheres + h]; }

  bool has_emitted() const { return !emitted.empty(); }
  const glm::mat3& emitted_at(size_t vertex, int h) const {
    return emitted[vertex * kGridHemispheres + h];
  }
  glm::mat3& emitted_at(size_t vertex, int h) { return emitted[vertex * kGridHemispheres + h]; }

  // Bytes a grid of `vertex_count` vertices holds in memory (for budget checks before
  // allocating).
  static size_t bytes_for(size_t vertex_count, bool with_emitted = false) {
    return vertex_count * ((with_emitted ? 2 : 1) * kGridHemispheres * sizeof(glm::mat3) + 1);
  }
};

// The grid the web page streams: the vectors plus the emitted light, in one component (the
// page draws lamps directly and nothing else, so the world's and emitters' direct light
// comes from the grid, soft and without sharp shadows; docs/ivg.md).
inline IrradianceVectorGrid grid_with_emitted_light(const IrradianceVectorGrid& grid) {
  IrradianceVectorGrid sum = grid;
  if (!sum.has_emitted()) return sum;
  for (size_t i = 0; i < sum.vectors.size(); ++i) sum.vectors[i] += grid.emitted[i];
  sum.emitted.clear();
  return sum;
}

}  // namespace bakegi
