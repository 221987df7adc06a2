#include "solvers/meshless/gather_integral.h"

#include <cmath>

#include "lights/surface_point.h"
#include "scene/phong_lobe.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "solvers/meshless/level_completion.h"
#include "solvers/meshless/visible_basis.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::meshless {

namespace {

// Uniform on the hemisphere around +z: z = u1 is uniform in solid angle.
glm::vec3 uniform_hemisphere(float u1, float u2) {
  const float z = u1;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u2;
  return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
}

}  // namespace

std::vector<glm::vec3> glossy_as_diffuse(const Scene& scene) {
  std::vector<glm::vec3> folded(scene.description.materials.size(), glm::vec3(0.0f));
  for (size_t m = 0; m < folded.size(); ++m) {
    const Material& material = scene.description.materials[m];
    if (material.has_glossy()) {
      folded[m] = material.glossy * float(phong_hemispherical_albedo(material.glossy_exponent));
    }
  }
  return folded;
}

uint64_t gather_links(const Scene& scene, const RayTracer& tracer, const BasisHierarchy& senders,
                      const glm::vec3& position, const glm::vec3& normal, uint64_t receiver,
                      const GatherSettings& settings, SenderAccumulator& out,
                      std::vector<BasisValue>& scratch, uint64_t* visibility_rays,
                      uint64_t* hits_completed) {
  const uint32_t rays = std::max(1u, settings.rays);
  const uint32_t side = static_cast<uint32_t>(std::sqrt(static_cast<double>(rays)));
  const uint32_t stratified = side * side;
  const float ray_weight = 2.0f * kPi / static_cast<float>(rays);
  const Frame frame(normal);
  RandomStream rng = sample_stream(settings.seed, receiver, 0);
  const glm::vec3 origin = position + normal * settings.ray_epsilon;
  const RayTracer* visibility = settings.visibility ? &tracer : nullptr;
  std::vector<BasisValue> candidates;
  uint64_t occlusion_rays = 0, completed_hits = 0;

  for (uint32_t r = 0; r < rays; ++r) {
    float u1 = rng.next_float(), u2 = rng.next_float();
    if (r < stratified) {  // jittered strata; the remainder (rays - side^2) is purely random
      u1 = (static_cast<float>(r % side) + u1) / static_cast<float>(side);
      u2 = (static_cast<float>(r / side) + u2) / static_cast<float>(side);
    }
    const glm::vec3 direction = frame.to_world(uniform_hemisphere(u1, u2));
    const Hit hit = tracer.intersect(Ray{origin, direction});
    if (!hit.hit) continue;
    const Triangle& triangle = scene.triangles[hit.triangle];
    glm::vec3 albedo = scene.albedo_at(triangle, hit.b1, hit.b2);
    if (settings.glossy_as_diffuse) albedo += (*settings.glossy_as_diffuse)[triangle.material];
    if (albedo.x <= 0.0f && albedo.y <= 0.0f && albedo.z <= 0.0f) continue;
    const SurfacePoint y = surface_at_hit(scene, hit, direction);
    // ω̄ points from the receiver towards the sender (where the light comes from).
    const glm::vec3 reflected = albedo * (kInvPi * ray_weight);
    scratch.clear();
    for (uint32_t level = 0; level < senders.level_count(); ++level) {
      gather_visible_basis(senders, visibility, level, y.position, y.shading_normal, scratch,
                           candidates, occlusion_rays);
    }
    if (settings.completion != nullptr) {
      if (complete_missing_levels(senders, *settings.completion, scratch) > 0) ++completed_hits;
    }
    for (const BasisValue& b : scratch) {
      LinkValue& link = out.at(b.index);
      for (int c = 0; c < 3; ++c) link[c] += (reflected[c] * b.value) * direction;
    }
  }
  if (visibility_rays != nullptr) *visibility_rays += occlusion_rays;
  if (hits_completed != nullptr) *hits_completed += completed_hits;
  return rays;
}

}  // namespace bakegi::meshless
