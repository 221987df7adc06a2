#include "lights/emissive_triangles.h"

#include <algorithm>
#include <cmath>

#include "scene/triangle_cells.h"
#include "util/sampling.h"

namespace bakegi {

EmissiveTriangles::EmissiveTriangles(const Scene& scene) : scene_(scene) {
  const EmissionCells& cells = scene.emission_cells;
  std::vector<double> weights;
  std::vector<double> cell_areas;
  double total = 0.0;
  for (size_t e = 0; e < scene.emissive_triangles.size(); ++e) {
    const uint32_t index = scene.emissive_triangles[e];
    const Triangle& t = scene.triangles[index];
    const uint32_t level = cells.level[e];
    const double cell_area = double(t.area) / double(triangle_cell_count(level));
    double emitter_weight = 0.0;
    for (uint64_t c = cells.first[e]; c < cells.first[e + 1]; ++c) {
      emitter_weight += cell_area * double(cells.power[c]);
    }
    if (!(emitter_weight > 0.0)) continue;
    emitters_.push_back({index, level, uint64_t(weights.size())});
    for (uint64_t c = cells.first[e]; c < cells.first[e + 1]; ++c) {
      weights.push_back(cell_area * double(cells.power[c]));
      cell_areas.push_back(cell_area);
      total += weights.back();
    }
  }
  if (emitters_.empty()) return;
  emitter_of_triangle_.assign(scene.triangles.size(), kNotSampled);
  for (size_t e = 0; e < emitters_.size(); ++e) {
    emitter_of_triangle_[emitters_[e].triangle] = uint32_t(e);
  }
  cdf_.reserve(weights.size());
  cell_pdf_over_area_.reserve(weights.size());
  double running = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    cdf_.push_back(running / total);
    cell_pdf_over_area_.push_back(float(weights[i] / total / cell_areas[i]));
  }
  cdf_.back() = 1.0;
}

bool EmissiveTriangles::sample(const glm::vec3& p, float u_pick, float u1, float u2,
                               LightSample& out) const {
  if (empty()) return false;
  const size_t cell = std::min<size_t>(
      size_t(std::upper_bound(cdf_.begin(), cdf_.end(), double(u_pick)) - cdf_.begin()),
      cdf_.size() - 1);
  const auto after =
      std::upper_bound(emitters_.begin(), emitters_.end(), uint64_t(cell),
                       [](uint64_t c, const Emitter& emitter) { return c < emitter.first_cell; });
  const Emitter& emitter = *(after - 1);
  const Triangle& t = scene_.triangles[emitter.triangle];
  const auto corners = triangle_cell_corners(emitter.level, uint32_t(cell - emitter.first_cell));
  const glm::vec2 b =
      triangle_cell_point(emitter.level, corners, sample_triangle_barycentrics(u1, u2));
  const glm::vec3 q = t.p[0] * (1.0f - b.x - b.y) + t.p[1] * b.x + t.p[2] * b.y;
  const glm::vec3 to_q = q - p;
  const float distance = glm::length(to_q);
  if (!(distance > 0.0f)) return false;
  out.direction = to_q / distance;
  const glm::vec3 radiance = emitted(emitter.triangle, b.x, b.y, out.direction);
  const float cos_light = std::abs(glm::dot(t.face_normal, out.direction));
  if (cos_light <= 0.0f || max_component(radiance) <= 0.0f) return false;
  out.distance = distance;
  out.pdf = cell_pdf_over_area_[cell] * distance * distance / cos_light;
  out.contribution = radiance / out.pdf;
  return true;
}

glm::vec3 EmissiveTriangles::emitted(uint32_t triangle, float b1, float b2,
                                     const glm::vec3& direction) const {
  // The material first: most hits are on surfaces that emit nothing, and the Triangle's
  // load is a cache miss.
  const Material& m = scene_.material_of(triangle);
  if (!m.is_emissive()) return glm::vec3(0.0f);
  const Triangle& t = scene_.triangles[triangle];
  if (!m.emission_two_sided && glm::dot(t.face_normal, direction) >= 0.0f) return glm::vec3(0.0f);
  return scene_.emission_at(t, b1, b2);
}

float EmissiveTriangles::pdf(uint32_t triangle, float b1, float b2, float distance,
                             float cos_light) const {
  if (emitter_of_triangle_.empty() || !(cos_light > 0.0f)) return 0.0f;
  const uint32_t e = emitter_of_triangle_[triangle];
  if (e == kNotSampled) return 0.0f;
  const Emitter& emitter = emitters_[e];
  const uint64_t cell = emitter.first_cell + triangle_cell_containing(emitter.level, b1, b2);
  return cell_pdf_over_area_[cell] * distance * distance / cos_light;
}

}  // namespace bakegi
