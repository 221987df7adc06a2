#include "solvers/antiradiance/surface_interpolation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "scene/lifted_visibility.h"
#include "scene/ray_tracer.h"

namespace bakegi::antiradiance {
namespace {

// Keeps the grid's memory proportional to the samples (a few cells per sample) however the
// samples are spread out; the cells grow instead.
constexpr double kMaxCellsPerSample = 4.0;
constexpr double kMinCells = 64.0;

float power(float x, int exponent) {
  float result = 1.0f;
  for (int i = 0; i < exponent; ++i) result *= x;
  return result;
}

}  // namespace

SurfaceInterpolation::SurfaceInterpolation(std::vector<SurfaceSample> samples,
                                           const RayTracer* visibility)
    : samples_(std::move(samples)), visibility_(visibility) {
  if (samples_.empty()) return;
  double area = 0.0;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const SurfaceSample& s : samples_) {
    area += double(s.area);
    lo = glm::min(lo, s.center);
    hi = glm::max(hi, s.center);
  }
  const float typical_edge = float(std::sqrt(2.0 * area / double(samples_.size())));
  support_ = kSupportInEdges * typical_edge;
  supports_.resize(samples_.size());
  float largest = support_;
  for (size_t i = 0; i < samples_.size(); ++i) {
    supports_[i] = std::max(support_, 1.25f * samples_[i].radius);
    largest = std::max(largest, supports_[i]);
  }
  if (!(largest > 0.0f) || !std::isfinite(largest)) {
    largest = std::max(glm::length(hi - lo), 1e-6f);
    if (!(support_ > 0.0f)) support_ = largest;
    for (float& h : supports_) h = std::max(h, support_);
  }

  const glm::vec3 size = hi - lo;
  const double max_cells = std::max(kMinCells, kMaxCellsPerSample * double(samples_.size()));
  cell_size_ = largest;
  for (;;) {
    const glm::dvec3 dims = glm::floor(glm::dvec3(size) / double(cell_size_)) + 1.0;
    if (dims.x * dims.y * dims.z <= max_cells) {
      dims_ = glm::ivec3(dims);
      break;
    }
    cell_size_ *= 1.25f;
  }
  origin_ = lo;

  const size_t cells = size_t(dims_.x) * size_t(dims_.y) * size_t(dims_.z);
  cell_offsets_.assign(cells + 1, 0);
  std::vector<uint32_t> sample_cell(samples_.size());
  for (size_t i = 0; i < samples_.size(); ++i) {
    sample_cell[i] = uint32_t(cell_index(cell_of(samples_[i].center)));
    ++cell_offsets_[sample_cell[i] + 1];
  }
  for (size_t c = 0; c < cells; ++c) cell_offsets_[c + 1] += cell_offsets_[c];
  cell_samples_.resize(samples_.size());
  std::vector<uint32_t> fill(cell_offsets_.begin(), cell_offsets_.end() - 1);
  for (size_t i = 0; i < samples_.size(); ++i) cell_samples_[fill[sample_cell[i]]++] = uint32_t(i);
}

glm::ivec3 SurfaceInterpolation::cell_of(const glm::vec3& position) const {
  glm::vec3 f = (position - origin_) / cell_size_;
  // Non-finite positions land in cell 0 rather than indexing out of range.
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(f[a])) f[a] = 0.0f;
  }
  const glm::ivec3 cell(glm::floor(glm::clamp(f, glm::vec3(-1.0f), glm::vec3(dims_))));
  return glm::clamp(cell, glm::ivec3(0), dims_ - 1);
}

glm::vec3 SurfaceInterpolation::evaluate(const glm::vec3& position, const glm::vec3& normal,
                                         bool* off_surface) const {
  if (off_surface) *off_surface = false;
  if (samples_.empty()) return glm::vec3(0.0f);
  struct Candidate {
    uint32_t sample;
    double weight;
  };
  // Reused per thread: evaluate() runs once per bake point.
  thread_local std::vector<Candidate> candidates;
  candidates.clear();
  const glm::ivec3 center = cell_of(position);
  const glm::ivec3 lo = glm::max(center - 1, glm::ivec3(0));
  const glm::ivec3 hi = glm::min(center + 1, dims_ - 1);
  for (int z = lo.z; z <= hi.z; ++z) {
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int x = lo.x; x <= hi.x; ++x) {
        const size_t cell = cell_index({x, y, z});
        for (uint32_t k = cell_offsets_[cell]; k < cell_offsets_[cell + 1]; ++k) {
          const uint32_t i = cell_samples_[k];
          const SurfaceSample& s = samples_[i];
          const float agreement = glm::dot(s.normal, normal);
          if (!(agreement > kMinNormalAgreement)) continue;
          const glm::vec3 offset = position - s.center;
          const float off_plane = glm::dot(offset, s.normal);
          const float d2 = glm::dot(offset, offset) + kPlaneDistanceWeight * off_plane * off_plane;
          const float h = supports_[i];
          const float t2 = d2 / (h * h);
          if (!(t2 < 1.0f)) continue;
          const float falloff = (1.0f - t2) * (1.0f - t2);
          candidates.push_back({i, double(falloff) * double(power(agreement, kNormalExponent))});
        }
      }
    }
  }
  glm::dvec3 sum(0.0), all_sum(0.0);
  double weight_sum = 0.0, all_weight_sum = 0.0;
  for (const Candidate& c : candidates) {
    const SurfaceSample& s = samples_[c.sample];
    all_sum += c.weight * glm::dvec3(s.value);
    all_weight_sum += c.weight;
    if (visibility_ != nullptr && !sees(position, normal, s)) continue;
    sum += c.weight * glm::dvec3(s.value);
    weight_sum += c.weight;
  }
  if (weight_sum > 0.0 && std::isfinite(weight_sum)) return glm::vec3(sum / weight_sum);
  if (all_weight_sum > 0.0 && std::isfinite(all_weight_sum)) {
    return glm::vec3(all_sum / all_weight_sum);
  }
  return nearest_fallback(position, normal, off_surface);
}

bool SurfaceInterpolation::sees(const glm::vec3& position, const glm::vec3& normal,
                                const SurfaceSample& s) const {
  return lifted_points_see_each_other(*visibility_, position, normal, s.center, s.normal,
                                      kLiftAbsolute * support_, kLiftPerDistance);
}

glm::vec3 SurfaceInterpolation::nearest_fallback(const glm::vec3& position, const glm::vec3& normal,
                                                 bool* off_surface) const {
  // Rare (points away from all geometry, or at odd normals): a linear scan ranked first by
  // how well the normal agrees (agreeing, same hemisphere, any), then by distance.
  int best_rank = 3;
  float best_distance = std::numeric_limits<float>::infinity();
  size_t best = 0;
  float clearance = std::numeric_limits<float>::infinity();  // beyond the nearest patch's extent
  for (size_t i = 0; i < samples_.size(); ++i) {
    const float agreement = glm::dot(samples_[i].normal, normal);
    clearance =
        std::min(clearance, glm::length(position - samples_[i].center) - samples_[i].radius);
    const int rank = agreement > kMinNormalAgreement ? 0 : (agreement > 0.0f ? 1 : 2);
    const glm::vec3 offset = position - samples_[i].center;
    float d2 = glm::dot(offset, offset);
    if (!std::isfinite(d2)) d2 = std::numeric_limits<float>::max();
    if (rank < best_rank || (rank == best_rank && d2 < best_distance)) {
      best_rank = rank;
      best_distance = d2;
      best = i;
    }
  }
  if (off_surface) *off_surface = !(clearance <= support_);
  return samples_[best].value;
}

size_t SurfaceInterpolation::memory_bytes() const {
  return samples_.capacity() * sizeof(SurfaceSample) + supports_.capacity() * sizeof(float) +
         (cell_offsets_.capacity() + cell_samples_.capacity()) * sizeof(uint32_t);
}

}  // namespace bakegi::antiradiance
