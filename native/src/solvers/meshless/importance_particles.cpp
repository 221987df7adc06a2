#include "solvers/meshless/importance_particles.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/sampling.h"

namespace bakegi::meshless {

namespace {

// Same scale as the direct light's offset: leaves the surface after float rounding of hit
// points, small against any feature worth a basis function.
constexpr float kRelativeRayEpsilon = 1e-5f;

glm::vec3 uniform_sphere(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u2;
  return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
}

}  // namespace

float placement_ray_epsilon(const Scene& scene) {
  const glm::vec3 magnitude = glm::max(glm::abs(scene.bounds_min), glm::abs(scene.bounds_max));
  const float scale = std::max({scene.extent(), max_component(magnitude), 1e-3f});
  return kRelativeRayEpsilon * scale;
}

ImportanceParticles::ImportanceParticles(const Scene& scene, const RayTracer& tracer,
                                         const glm::vec3& viewpoint,
                                         const ParticleSettings& settings)
    : scene_(scene),
      tracer_(tracer),
      settings_(settings),
      epsilon_(placement_ray_epsilon(scene)),
      from_viewpoint_(true),
      viewpoint_(viewpoint) {
  if (!std::isfinite(viewpoint.x) || !std::isfinite(viewpoint.y) || !std::isfinite(viewpoint.z)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless placement: the viewpoint is not finite");
  }
}

ImportanceParticles::ImportanceParticles(const Scene& scene, const RayTracer& tracer,
                                         const BakePoints& sources,
                                         const ParticleSettings& settings)
    : scene_(scene),
      tracer_(tracer),
      settings_(settings),
      epsilon_(placement_ray_epsilon(scene)),
      from_viewpoint_(false),
      sources_(sources) {
  if (sources_.size() == 0 || sources_.normals.size() != sources_.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless placement: no source points to start importance particles from");
  }
}

ImportanceParticles::Start ImportanceParticles::start(RandomStream& random) const {
  if (from_viewpoint_) {
    const float u1 = random.next_float(), u2 = random.next_float();
    return {viewpoint_, uniform_sphere(u1, u2)};
  }
  const size_t count = sources_.size();
  const size_t index = std::min(count - 1, size_t(double(random.next_float()) * double(count)));
  const glm::vec3 normal = sources_.normals[index];
  const float u1 = random.next_float(), u2 = random.next_float();
  const glm::vec3 direction = Frame(normal).to_world(sample_cosine_hemisphere(u1, u2));
  return {sources_.positions[index] + normal * epsilon_, direction};
}

void ImportanceParticles::trace(uint64_t particle, std::vector<Candidate>& out,
                                uint64_t& rays) const {
  RandomStream random = sample_stream(settings_.seed, particle, 0);
  Start ray = start(random);
  uint32_t escapes = 0;
  for (uint32_t bounce = 0; bounce < settings_.bounces;) {
    ++rays;
    const Hit hit = tracer_.intersect(Ray{ray.origin, ray.direction, 0.0f, 1e30f});
    if (!hit.hit) {
      // Escaped: start again (the bounce count carries on, so an open scene still deposits).
      if (++escapes > settings_.max_escapes) return;
      ray = start(random);
      continue;
    }
    const SurfacePoint x = surface_at_hit(scene_, hit, ray.direction);
    ++bounce;
    if (bounce > settings_.skipped_bounces) {
      out.push_back(Candidate{x.position, x.shading_normal, x.geometric_normal, hit.triangle});
    }
    // Diffuse reflection about the geometric normal: the particle stays on the side it came
    // from, so it never crosses a surface.
    const float u1 = random.next_float(), u2 = random.next_float();
    ray.direction = Frame(x.geometric_normal).to_world(sample_cosine_hemisphere(u1, u2));
    ray.origin = x.position + x.geometric_normal * epsilon_;
  }
}

size_t ImportanceParticles::next_batch(std::vector<Candidate>& out) {
  const size_t count = std::max<uint32_t>(1, settings_.batch_particles);
  std::vector<std::vector<Candidate>> per_particle(count);
  std::vector<uint64_t> per_particle_rays(count, 0);
  const uint64_t first = next_particle_;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 16), [&](const auto& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      per_particle[i].reserve(settings_.bounces);
      trace(first + i, per_particle[i], per_particle_rays[i]);
    }
  });
  next_particle_ += count;
  size_t appended = 0;
  for (size_t i = 0; i < count; ++i) {
    out.insert(out.end(), per_particle[i].begin(), per_particle[i].end());
    appended += per_particle[i].size();
    rays_ += per_particle_rays[i];
  }
  if (appended == 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                from_viewpoint_
                    ? "meshless placement: no importance particle from the viewpoint stayed in "
                      "the scene long enough to find surfaces; put the viewpoint inside the "
                      "scene, facing surfaces"
                    : "meshless placement: no importance particle from the bake points stayed "
                      "in the scene long enough to find surfaces");
  }
  return appended;
}

}  // namespace bakegi::meshless
