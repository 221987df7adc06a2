#include "diffuse_rays.h"

#include <algorithm>

#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::bench {

namespace {

struct SurfacePoint {
  glm::vec3 position;
  glm::vec3 normal;
};

// Uniform over the scene's surface area, through the cumulative area table.
class SurfaceSampler {
 public:
  explicit SurfaceSampler(const Scene& scene) : scene_(scene), cumulative_(scene.triangles.size()) {
    for (size_t t = 0; t < scene.triangles.size(); ++t) {
      total_ += scene.triangles[t].area;
      cumulative_[t] = total_;
    }
  }

  SurfacePoint sample(Pcg32& random) const {
    const double pick = random.next_float() * total_;
    const size_t t = std::min<size_t>(
        std::upper_bound(cumulative_.begin(), cumulative_.end(), pick) - cumulative_.begin(),
        cumulative_.size() - 1);
    const Triangle& tri = scene_.triangles[t];
    const glm::vec2 b = sample_triangle_barycentrics(random.next_float(), random.next_float());
    return {(1.0f - b.x - b.y) * tri.p[0] + b.x * tri.p[1] + b.y * tri.p[2], tri.face_normal};
  }

 private:
  const Scene& scene_;
  std::vector<double> cumulative_;
  double total_ = 0.0;
};

}  // namespace

std::vector<Ray> diffuse_bounce_rays(const Scene& scene, size_t count, uint64_t seed) {
  const SurfaceSampler surface(scene);
  // Offsets the origin off its surface as a bounce would, relative to the scene size.
  const float epsilon = 1e-4f * scene.extent();
  Pcg32 random(mix64(seed), 1);
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    const SurfacePoint p = surface.sample(random);
    const glm::vec3 local = sample_cosine_hemisphere(random.next_float(), random.next_float());
    ray.origin = p.position + epsilon * p.normal;
    ray.direction = Frame(p.normal).to_world(local);
    ray.tnear = 0.0f;
    ray.tfar = 1e30f;
  }
  return rays;
}

std::vector<Ray> surface_to_surface_segments(const Scene& scene, size_t count, uint64_t seed) {
  const SurfaceSampler surface(scene);
  const float epsilon = 1e-4f * scene.extent();
  Pcg32 random(mix64(seed), 2);
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    const SurfacePoint from = surface.sample(random);
    const SurfacePoint to = surface.sample(random);
    ray.origin = from.position + epsilon * from.normal;
    ray.direction = to.position - ray.origin;  // t in [0, 1] spans the segment
    ray.tnear = 0.0f;
    ray.tfar = 1.0f - 1e-3f;
  }
  return rays;
}

}  // namespace bakegi::bench
