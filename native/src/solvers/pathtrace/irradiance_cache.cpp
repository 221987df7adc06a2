#include "solvers/pathtrace/irradiance_cache.h"

#include <algorithm>
#include <cmath>

#include "util/luminance.h"

namespace bakegi {

namespace {

// A point lies "behind" record i (in front of its surface, seen from x: a concave corner's
// other wall) when (x − x_i) · (n + n_i)/2 is below this fraction of the record's reach
// (Ward et al.'s test, scaled to the record instead of the scene's units).
constexpr float kBehindTolerance = 0.05f;

glm::vec3 channel_dot(const std::array<glm::vec3, 3>& gradient, const glm::vec3& d) {
  return {glm::dot(gradient[0], d), glm::dot(gradient[1], d), glm::dot(gradient[2], d)};
}

}  // namespace

float record_radius(const IrradianceGather& gather, float max_radius) {
  float radius = std::min(gather.harmonic_distance, max_radius);
  const glm::vec3 luminance_gradient = 0.2126f * gather.translational[0] +
                                       0.7152f * gather.translational[1] +
                                       0.0722f * gather.translational[2];
  const float slope = glm::length(luminance_gradient);
  const float y = float(luminance(gather.value));
  if (slope > 0.0f && y > 0.0f) radius = std::min(radius, y / slope);
  return std::max(radius, 0.0f);
}

size_t RecordIndex::KeyHash::operator()(const Key& k) const {
  uint64_t h = uint64_t(uint32_t(k.level));
  for (const int32_t v : {k.x, k.y, k.z}) h = (h ^ uint64_t(uint32_t(v))) * 0x100000001b3ull;
  return size_t(h ^ (h >> 29));
}

RecordIndex::Key RecordIndex::key_of(int level, const glm::vec3& p) const {
  const float cell = std::ldexp(smallest_cell_, level);
  return {level, int32_t(std::floor(p.x / cell)), int32_t(std::floor(p.y / cell)),
          int32_t(std::floor(p.z / cell))};
}

void RecordIndex::insert(uint32_t record, const glm::vec3& centre, float reach) {
  int level = 0;
  if (reach > smallest_cell_)
    level = std::min(31, int(std::ceil(std::log2(reach / smallest_cell_))));
  // Rounding: make sure the cell is at least the reach.
  while (level < 31 && std::ldexp(smallest_cell_, level) < reach) ++level;
  levels_in_use_ |= 1u << level;
  cells_[key_of(level, centre)].push_back(record);
}

uint32_t IrradianceCache::add(const IrradianceRecord& record) {
  const uint32_t id = uint32_t(records_.size());
  records_.push_back(record);
  index_.insert(id, record.position, accuracy_ * record.radius);
  return id;
}

float IrradianceCache::error_of(const IrradianceRecord& record, const glm::vec3& x,
                                const glm::vec3& n, float own_radius) const {
  const float cosine = glm::dot(n, record.normal);
  if (!(cosine > 0.0f) || !(record.radius > 0.0f)) return accuracy_;
  const glm::vec3 d = x - record.position;
  const float reach = accuracy_ * record.radius;
  if (glm::dot(d, 0.5f * (n + record.normal)) < -kBehindTolerance * reach) return accuracy_;
  const float radius = std::min(record.radius, own_radius);
  if (!(radius > 0.0f)) return accuracy_;
  return glm::length(d) / radius + std::sqrt(std::max(0.0f, 1.0f - cosine));
}

bool IrradianceCache::covers(const glm::vec3& x, const glm::vec3& n, float own_radius,
                             uint32_t except) const {
  bool found = false;
  index_.for_each_near(x, [&](uint32_t i) {
    if (!found && i != except && error_of(records_[i], x, n, own_radius) < accuracy_) found = true;
  });
  return found;
}

IrradianceCache::Interpolated IrradianceCache::interpolate(const glm::vec3& x, const glm::vec3& n,
                                                           float own_radius,
                                                           uint32_t except) const {
  glm::dvec3 sum(0.0);
  double weights = 0.0, variance = 0.0;
  index_.for_each_near(x, [&](uint32_t i) {
    if (i == except) return;
    const IrradianceRecord& record = records_[i];
    const float error = error_of(record, x, n, own_radius);
    if (!(error < accuracy_)) return;
    // A record at the point itself: its weight is infinite, the others' nothing.
    const double w = 1.0 / std::max(double(error), 1e-6) - 1.0 / double(accuracy_);
    const glm::vec3 turned = glm::cross(record.normal, n);
    const glm::vec3 prediction = record.gather.value +
                                 channel_dot(record.gather.rotational, turned) +
                                 channel_dot(record.gather.translational, x - record.position);
    sum += w * glm::dvec3(glm::max(prediction, glm::vec3(0.0f)));
    weights += w;
    variance += w * w * double(record.gather.luminance_variance_of_mean);
  });
  Interpolated out;
  if (weights > 0.0) {
    out.covered = true;
    out.value = glm::vec3(sum / weights);
    out.luminance_variance_of_mean = float(variance / (weights * weights));
  }
  return out;
}

}  // namespace bakegi
