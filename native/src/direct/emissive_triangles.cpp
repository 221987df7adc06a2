#include "direct/emissive_triangles.h"

#include <algorithm>
#include <cmath>

#include "util/sampling.h"

namespace bakegi {

namespace {

float emission_weight(const glm::vec3& emission) {
  return std::max(0.0f, emission.x) + std::max(0.0f, emission.y) + std::max(0.0f, emission.z);
}

}  // namespace

EmissiveTriangles::EmissiveTriangles(const Scene& scene) : scene_(scene) {
  std::vector<double> weights;
  double total = 0.0;
  for (uint32_t index : scene.emissive_triangles) {
    const Triangle& t = scene.triangles[index];
    const double w = double(t.area) * emission_weight(scene.material_of(t).emission);
    if (!(w > 0.0)) continue;
    triangles_.push_back(index);
    weights.push_back(w);
    total += w;
  }
  if (triangles_.empty()) return;
  pick_pdf_over_area_.assign(scene.triangles.size(), 0.0f);
  cdf_.reserve(weights.size());
  double running = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    cdf_.push_back(running / total);
    const Triangle& t = scene.triangles[triangles_[i]];
    pick_pdf_over_area_[triangles_[i]] = float(weights[i] / total / double(t.area));
  }
  cdf_.back() = 1.0;
}

bool EmissiveTriangles::sample(const glm::vec3& p, float u_pick, float u1, float u2,
                               LightSample& out) const {
  if (empty()) return false;
  const size_t i = std::min<size_t>(
      size_t(std::upper_bound(cdf_.begin(), cdf_.end(), double(u_pick)) - cdf_.begin()),
      cdf_.size() - 1);
  const uint32_t index = triangles_[i];
  const Triangle& t = scene_.triangles[index];
  const glm::vec2 b = sample_triangle_barycentrics(u1, u2);
  const glm::vec3 q = t.p[0] * (1.0f - b.x - b.y) + t.p[1] * b.x + t.p[2] * b.y;
  const glm::vec3 to_q = q - p;
  const float distance = glm::length(to_q);
  if (!(distance > 0.0f)) return false;
  out.direction = to_q / distance;
  const glm::vec3 radiance = emitted(index, out.direction);
  const float cos_light = std::abs(glm::dot(t.face_normal, out.direction));
  if (cos_light <= 0.0f || max_component(radiance) <= 0.0f) return false;
  out.distance = distance;
  out.pdf = pdf(index, distance, cos_light);
  out.contribution = radiance / out.pdf;
  return true;
}

glm::vec3 EmissiveTriangles::emitted(uint32_t triangle, const glm::vec3& direction) const {
  const Triangle& t = scene_.triangles[triangle];
  const Material& m = scene_.material_of(t);
  if (!m.emission_two_sided && glm::dot(t.face_normal, direction) >= 0.0f) return glm::vec3(0.0f);
  return m.emission;
}

float EmissiveTriangles::pdf(uint32_t triangle, float distance, float cos_light) const {
  if (pick_pdf_over_area_.empty() || !(cos_light > 0.0f)) return 0.0f;
  return pick_pdf_over_area_[triangle] * distance * distance / cos_light;
}

}  // namespace bakegi
