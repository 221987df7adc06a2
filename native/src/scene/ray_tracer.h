// The one place that talks to Embree (3 on Debian 12; 4 builds through the same calls,
// see ray_tracer.cpp). Solvers and the direct-light module see only this interface.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct Scene;

struct Ray {
  glm::vec3 origin;
  glm::vec3 direction;  // need not be normalized; t is in units of |direction|
  float tnear = 0.0f;
  float tfar = 1e30f;
  // Tells apart rays that share origin and direction where they meet see-through surfaces
  // (scene/passing_surfaces.h): a sample's own random numbers, hashed; 0 where it does not
  // matter.
  uint32_t seed = 0;
};

struct Hit {
  bool hit = false;
  float t = 0.0f;
  uint32_t triangle = 0;       // index into Scene::triangles
  float b1 = 0.0f, b2 = 0.0f;  // barycentrics of corners 1 and 2
  // From the ray and Embree, so that a hit's surface point needs no load of its Triangle
  // (a cache miss after every ray): origin + t * direction, and Embree's geometric normal
  // (not unit; either side).
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
};

// A ray as traced, for the benchmark that replays a solver's own rays through Embree alone.
struct RecordedRay {
  Ray ray;
  bool occlusion = false;  // occluded() rather than intersect()
};

struct RayTracerOptions {
  // Embree's own allocations above this many bytes fail the build with OUT_OF_MEMORY
  // (0 = no limit).
  size_t memory_budget_bytes = 0;
  // Called during the build with the fraction done; returning false stops the build
  // (the constructor then throws Error(CANCELLED)). May be called from several threads.
  std::function<bool(double)> progress;
};

class RayTracer {
 public:
  // Builds the BVH over scene.triangles. Throws bakegi::Error on Embree errors.
  explicit RayTracer(const Scene& scene, const RayTracerOptions& options = {});
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  Hit intersect(const Ray& ray) const;
  bool occluded(const Ray& ray) const;  // any hit in (tnear, tfar)
  // Packets of rays, for throughput benchmarks (the Embree limit).
  void intersect_many(const Ray* rays, Hit* hits, size_t count) const;
  // Rays on the caller's thread through Embree 3's stream interface (rtcIntersect1M /
  // rtcOccluded1M), `chunk` rays a call (at most kMaxStreamChunk); one ray at a time with
  // Embree 4, which has none. Results equal intersect() / occluded() ray by ray. For the
  // benchmarks: on the path tracer's own rays it traces 16-22% more rays a second than
  // single rays (docs/benchmarks.md, section 0n).
  static constexpr size_t kMaxStreamChunk = 1024;
  void intersect_stream(const Ray* rays, Hit* hits, size_t count, size_t chunk) const;
  void occluded_stream(const Ray* rays, uint8_t* occluded, size_t count, size_t chunk) const;

  // Bytes Embree holds for this scene (counted by its memory monitor).
  size_t memory_bytes() const;
  // Whether some triangles let rays pass (glass, cut-outs): then every ray passes each of
  // them with its material's probability, and a hit is the first surface a ray stopped at.
  bool has_passing_surfaces() const;

  // Appends every ray intersect() and occluded() trace to `log`, in order (null: off), so
  // that native/bench can time Embree alone on the path tracer's own rays. Not
  // thread-safe: record from one thread.
  void record_rays(std::vector<RecordedRay>* log) { log_ = log; }

 private:
  // Makes and attaches one triangle geometry: `subset` of scene.triangles (null: all), with
  // the pass filter where `passing`.
  void attach_triangles(const Scene& scene, const std::vector<uint32_t>* subset, bool passing);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<RecordedRay>* log_ = nullptr;
};

}  // namespace bakegi
