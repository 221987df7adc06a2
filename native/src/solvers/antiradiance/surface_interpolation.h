// The output of Antiradiance at bake points (§4.3, the "weighted splat"): per-patch indirect
// irradiance interpolated smoothly among the patches of the surface a bake point lies on.
//
// A bake point carries a position and a shading normal but no surface id, so "the same
// surface" means: patches whose centers lie within the support radius h_p and whose face
// normal agrees with the point's normal (⟨n_p, n⟩ > 0.5, within 60°). Each contributes
//
//   w_p = k(d_p / h_p) · ⟨n_p, n⟩^q,   k(t) = (1 − t²)² for t < 1, else 0,
//   d_p² = |x − c_p|² + 3 ⟨x − c_p, n_p⟩²,
//
// and the value is Σ w_p E_p / Σ w_p. k is C¹ and reaches 0 at h_p, so values vary smoothly
// as a point moves across patch borders (no seams). The normal-offset term counts distance
// off the patch's plane double, which keeps apart parallel surfaces that are close but
// separate (two sides of a thin slab face opposite ways and are excluded by the normal test
// already). q = 8 separates creases that the 0.5 threshold lets through: at 30° a neighbour
// weighs cos(30°)^8 = 0.32 of a coplanar one, at 45° 0.06, while the few-degree normal
// changes between facets of a tessellated curved surface cost almost nothing (cos(5°)^8 =
// 0.97). Box faces meet at 90° and never mix.
//
// h_p = max(h, 1.25 r_p): h is twice the typical patch edge sqrt(2 · mean patch area) (about
// 15 patch centers within h on a flat surface), r_p the patch's centroid-to-corner radius, so
// a point anywhere on a large patch still sees it. Lookup is a uniform grid over patch
// centers with cells no smaller than the largest h_p: the 3×3×3 cells around the point hold
// every candidate. When no weight is positive (a point far from every patch, or facing a way
// no nearby patch faces) the value of the nearest patch with an agreeing normal is used, else
// of the nearest patch facing the point's hemisphere, else of the nearest patch; never NaN.
//
// Visibility (optional, with a RayTracer): a patch whose center the bake point cannot see
// along the surface is left out. Without it a point on the floor next to a box that stands on
// it (boxes in Blender scenes have no bottom face) averages the dark floor patches hidden under
// the box, and a point under the box the lit ones outside: on the Cornell box this blur across
// the footprint's rim was 80% of the floor's squared error. The test is one occlusion ray per
// candidate between the point and the patch center, both lifted off their surfaces along their
// normals by kLiftAbsolute · h + kLiftPerDistance · |x − c_p|: the distance-proportional part
// keeps the segment outside convex tessellated surfaces (two points on a circle at an angle θ
// apart need a lift of about θ/8 of their distance; 0.15 covers θ up to 70°, beyond the 60°
// the normal test admits) while any occluder taller than that lift, standing between the two,
// still blocks. When every candidate is blocked the unblocked average is used (no better
// information; also what a point in a gap narrower than the patches gets).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {
class RayTracer;
}

namespace bakegi::antiradiance {

struct SurfaceSample {
  glm::vec3 center{0.0f};
  glm::vec3 normal{0.0f};  // unit
  float radius = 0.0f;     // centroid to farthest corner
  float area = 0.0f;
  glm::vec3 value{0.0f};  // what is interpolated (here: E_indirect / π)
};

class SurfaceInterpolation {
 public:
  static constexpr float kMinNormalAgreement = 0.5f;
  static constexpr int kNormalExponent = 8;
  static constexpr float kSupportInEdges = 2.0f;
  static constexpr float kPlaneDistanceWeight = 3.0f;
  static constexpr float kLiftAbsolute = 0.01f;     // of the support radius h
  static constexpr float kLiftPerDistance = 0.15f;  // of the point-to-center distance

  SurfaceInterpolation() = default;
  // `visibility` (optional) enables the visibility test; it must outlive every evaluate().
  explicit SurfaceInterpolation(std::vector<SurfaceSample> samples,
                                const RayTracer* visibility = nullptr);

  // The interpolated value at `position` with unit normal `normal`; zero when there are no
  // samples. Finite whenever the samples' values are. `off_surface` (optional) is set when the
  // point lies farther than the support radius beyond every patch (farther than h from each
  // patch's extent): its value is then only the nearest patch's, which says nothing about a
  // point in open space (a point a million metres away used to get it as its light).
  glm::vec3 evaluate(const glm::vec3& position, const glm::vec3& normal,
                     bool* off_surface = nullptr) const;

  float support_radius() const { return support_; }
  size_t sample_count() const { return samples_.size(); }
  size_t memory_bytes() const;

 private:
  glm::ivec3 cell_of(const glm::vec3& position) const;
  size_t cell_index(const glm::ivec3& cell) const {
    return (size_t(cell.z) * size_t(dims_.y) + size_t(cell.y)) * size_t(dims_.x) + size_t(cell.x);
  }
  glm::vec3 nearest_fallback(const glm::vec3& position, const glm::vec3& normal,
                             bool* off_surface) const;
  bool sees(const glm::vec3& position, const glm::vec3& normal, const SurfaceSample& s) const;

  std::vector<SurfaceSample> samples_;
  const RayTracer* visibility_ = nullptr;
  std::vector<float> supports_;         // h_p per sample
  std::vector<uint32_t> cell_offsets_;  // cell count + 1 entries into cell_samples_
  std::vector<uint32_t> cell_samples_;  // sample indices grouped by cell
  glm::vec3 origin_{0.0f};
  float cell_size_ = 1.0f;
  glm::ivec3 dims_{1, 1, 1};
  float support_ = 0.0f;
};

}  // namespace bakegi::antiradiance
