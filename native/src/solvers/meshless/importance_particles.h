// Candidates for the meshless point placement (Lehtinen et al. 2008, §2.3): importance
// particles traced from where the user looks (one valid viewpoint) or from the surfaces
// being baked, bouncing diffusely through the scene and leaving a candidate at every hit
// after the first few. Only surfaces light can reach from there get candidates, so solid
// interiors and the outsides of closed rooms get none.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bake_points.h"
#include "util/random.h"

namespace bakegi {
struct Scene;
class RayTracer;
}  // namespace bakegi

namespace bakegi::meshless {

// A point of a valid surface, seen from the side the particle arrived from.
struct Candidate {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};            // shading normal (what a BasisPoint holds)
  glm::vec3 geometric_normal{0.0f, 0.0f, 1.0f};  // the surface's side; rays leave along it
  uint32_t triangle = 0;                         // index into Scene::triangles
};

struct ParticleSettings {
  uint32_t bounces = 30;         // hits per particle (the paper's "30 bounces")
  uint32_t skipped_bounces = 3;  // the first hits are not deposited: they still depend
                                 // strongly on where the particles started
  uint32_t batch_particles = 1024;
  // A particle that escapes the scene starts again at its origin; after this many escapes
  // it is given up (an open scene can let most particles out).
  uint32_t max_escapes = 120;
  uint64_t seed = 0;
};

// Offset of ray origins from the surface, relative to the scene size (as the direct light's).
float placement_ray_epsilon(const Scene& scene);

class ImportanceParticles {
 public:
  // Particles start at `viewpoint` in uniformly random directions.
  ImportanceParticles(const Scene& scene, const RayTracer& tracer, const glm::vec3& viewpoint,
                      const ParticleSettings& settings);
  // Particles start at a uniformly chosen point of `sources` (e.g. bake points: the surfaces
  // that must be covered), cosine-distributed around its normal (its front side). The
  // points are copied. Throws Error(INVALID_ARGUMENT) when `sources` is empty.
  // A source inside a closed solid makes that solid's inside valid too (e.g. the corners of
  // a floor grid under the Cornell box's blocks: the blocks' inner faces then get points);
  // a viewpoint has no such problem.
  ImportanceParticles(const Scene& scene, const RayTracer& tracer, const BakePoints& sources,
                      const ParticleSettings& settings);

  // Traces the next `batch_particles` particles (in parallel) and appends their candidates
  // in particle order, so the sequence depends only on the seed, never on thread count.
  // Returns how many were appended. Throws Error(INVALID_ARGUMENT) when a whole batch
  // deposits nothing (the start sees no surface it can bounce around on).
  size_t next_batch(std::vector<Candidate>& out);

  uint64_t particles_traced() const { return next_particle_; }
  uint64_t rays_traced() const { return rays_; }

 private:
  struct Start {
    glm::vec3 origin;
    glm::vec3 direction;
  };
  Start start(RandomStream& random) const;
  void trace(uint64_t particle, std::vector<Candidate>& out, uint64_t& rays) const;

  const Scene& scene_;
  const RayTracer& tracer_;
  ParticleSettings settings_;
  float epsilon_;
  bool from_viewpoint_;
  glm::vec3 viewpoint_{0.0f};
  BakePoints sources_;
  uint64_t next_particle_ = 0;
  uint64_t rays_ = 0;
};

}  // namespace bakegi::meshless
