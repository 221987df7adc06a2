// The Embree wrapper. Embree 3 and 4 differ in the intersect/occluded calls (4 dropped
// RTCIntersectContext for optional argument structs) and in the include path; both are
// handled here and nowhere else.
#include "scene/ray_tracer.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <mutex>
#include <string>

#if BAKEGI_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/passing_surfaces.h"
#include "scene/scene.h"
#include "util/error.h"

namespace bakegi {

namespace {

RTCRay to_rtc_ray(const Ray& ray) {
  RTCRay r;
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = ray.tnear;
  r.tfar = ray.tfar;
  r.time = 0.0f;
  r.mask = std::numeric_limits<unsigned>::max();
  r.id = ray.seed;
  r.flags = 0;
  return r;
}

// A ray and an empty hit record, as rtcIntersect1 and rtcIntersect1M take them.
RTCRayHit to_rtc_ray_hit(const Ray& ray) {
  RTCRayHit rayhit;
  rayhit.ray = to_rtc_ray(ray);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rayhit;
}

const char* rtc_error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
    default:
      return "error";
  }
}

}  // namespace

struct RayTracer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RayTracerOptions options;

  std::mutex error_mutex;
  RTCError first_error = RTC_ERROR_NONE;
  std::string first_message;

  std::atomic<int64_t> memory{0};
  std::atomic<int64_t> peak_memory{0};

  // Geometry 0 holds the opaque triangles, geometry 1 (only where there are any) the passing
  // ones; a hit's primitive is turned back into a Scene::triangles index through these.
  std::unique_ptr<const PassingSurfaces> passing;
  std::vector<uint32_t> opaque_triangles;  // empty: geometry 0 is every triangle, in order

  uint32_t triangle_of(unsigned geometry, unsigned primitive) const {
    if (geometry == 1) return passing->triangle_indices()[primitive];
    return opaque_triangles.empty() ? primitive : opaque_triangles[primitive];
  }

  // The Hit of `ray` from Embree's record of it.
  Hit hit_of(const Ray& ray, const RTCRayHit& rayhit) const {
    Hit hit;
    if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.hit = true;
    hit.t = rayhit.ray.tfar;
    hit.triangle = triangle_of(rayhit.hit.geomID, rayhit.hit.primID);
    hit.b1 = rayhit.hit.u;
    hit.b2 = rayhit.hit.v;
    hit.position = ray.origin + hit.t * ray.direction;
    hit.normal = glm::vec3(rayhit.hit.Ng_x, rayhit.hit.Ng_y, rayhit.hit.Ng_z);
    return hit;
  }

  // Embree's filter for geometry 1: a hit the ray passes is rejected, so traversal goes on.
  static void pass_filter(const RTCFilterFunctionNArguments* args) {
    const auto* surfaces = static_cast<const PassingSurfaces*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
      if (args->valid[i] != -1) continue;
      RTCRayN* ray = args->ray;
      RTCHitN* hit = args->hit;
      const unsigned n = args->N;
      const glm::vec3 origin(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i),
                             RTCRayN_org_z(ray, n, i));
      const glm::vec3 direction(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i),
                                RTCRayN_dir_z(ray, n, i));
      if (surfaces->passes(RTCHitN_primID(hit, n, i), RTCHitN_u(hit, n, i), RTCHitN_v(hit, n, i),
                           RTCRayN_id(ray, n, i), origin, direction)) {
        args->valid[i] = 0;
      }
    }
  }

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->error_mutex);
    if (self->first_error != RTC_ERROR_NONE) return;
    self->first_error = code;
    self->first_message = message ? message : "";
  }

  // Embree asks before it allocates (post = false) and reports frees (bytes < 0).
  static bool on_memory(void* user, ssize_t bytes, bool post) {
    auto* self = static_cast<Impl*>(user);
    const int64_t now = self->memory.fetch_add(bytes) + bytes;
    if (bytes > 0 && !post && self->options.memory_budget_bytes > 0 &&
        now > int64_t(self->options.memory_budget_bytes)) {
      // Refused: Embree does not allocate, and does not report the matching free.
      self->memory.fetch_sub(bytes);
      return false;
    }
    int64_t peak = self->peak_memory.load();
    while (now > peak && !self->peak_memory.compare_exchange_weak(peak, now)) {
    }
    return true;
  }

  static bool on_progress(void* user, double fraction) {
    auto* self = static_cast<Impl*>(user);
    return !self->options.progress || self->options.progress(fraction);
  }

  // Throws the first error Embree reported, if any.
  void throw_if_failed(const char* during) {
    std::lock_guard lock(error_mutex);
    const RTCError code = first_error != RTC_ERROR_NONE ? first_error : rtcGetDeviceError(device);
    if (code == RTC_ERROR_NONE) return;
    const std::string text = std::string("Embree ") + rtc_error_name(code) + " during " + during +
                             (first_message.empty() ? "" : ": " + first_message);
    if (code == RTC_ERROR_CANCELLED) throw Error(BAKEGI_ERROR_CANCELLED, text);
    if (code == RTC_ERROR_OUT_OF_MEMORY) {
      throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                  text + (options.memory_budget_bytes > 0
                              ? " (memory budget " +
                                    std::to_string(options.memory_budget_bytes >> 20) + " MB)"
                              : ""));
    }
    throw Error(BAKEGI_ERROR_RAY_TRACER, text);
  }
};

RayTracer::RayTracer(const Scene& scene, const RayTracerOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) {
    const RTCError code = rtcGetDeviceError(nullptr);
    throw Error(BAKEGI_ERROR_RAY_TRACER,
                std::string("Embree could not create a device: ") + rtc_error_name(code));
  }
  // The error callback first, so that every later failure is recorded with its text.
  rtcSetDeviceErrorFunction(impl_->device, &Impl::on_error, impl_.get());
  rtcSetDeviceMemoryMonitorFunction(impl_->device, &Impl::on_memory, impl_.get());

  impl_->scene = rtcNewScene(impl_->device);
  impl_->throw_if_failed("scene creation");
  // Robust: no rays slip through the shared edges of triangles (closed rooms stay closed).
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneProgressMonitorFunction(impl_->scene, &Impl::on_progress, impl_.get());

  impl_->passing = std::make_unique<const PassingSurfaces>(scene);
  if (impl_->passing->empty()) {
    attach_triangles(scene, nullptr, false);
  } else {
    std::vector<bool> passes(scene.triangles.size(), false);
    for (uint32_t t : impl_->passing->triangle_indices()) passes[t] = true;
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
      if (!passes[t]) impl_->opaque_triangles.push_back(t);
    }
    attach_triangles(scene, &impl_->opaque_triangles, false);
    attach_triangles(scene, &impl_->passing->triangle_indices(), true);
  }
  rtcCommitScene(impl_->scene);
  impl_->throw_if_failed("BVH build");
}

RayTracer::~RayTracer() = default;

void RayTracer::attach_triangles(const Scene& scene, const std::vector<uint32_t>* subset,
                                 bool passing) {
  const size_t count = subset ? subset->size() : scene.triangles.size();
  // A scene all of glass has no opaque geometry: Embree refuses empty buffers.
  if (count == 0) return;
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  impl_->throw_if_failed("geometry creation");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    impl_->throw_if_failed("geometry buffer allocation");
    throw Error(BAKEGI_ERROR_RAY_TRACER, "Embree returned no geometry buffer");
  }
  for (size_t t = 0; t < count; ++t) {
    const Triangle& triangle = scene.triangles[subset ? (*subset)[t] : t];
    for (int c = 0; c < 3; ++c) {
      const glm::vec3& p = triangle.p[c];
      vertices[9 * t + 3 * c + 0] = p.x;
      vertices[9 * t + 3 * c + 1] = p.y;
      vertices[9 * t + 3 * c + 2] = p.z;
      indices[3 * t + c] = unsigned(3 * t + c);
    }
  }
  if (passing) {
    rtcSetGeometryUserData(geometry, const_cast<PassingSurfaces*>(impl_->passing.get()));
    rtcSetGeometryIntersectFilterFunction(geometry, &Impl::pass_filter);
    rtcSetGeometryOccludedFilterFunction(geometry, &Impl::pass_filter);
  }
  rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
  rtcCommitGeometry(geometry);
  // Fixed ids: 0 the opaque triangles, 1 the passing ones (Impl::triangle_of).
  rtcAttachGeometryByID(impl_->scene, geometry, passing ? 1u : 0u);
  rtcReleaseGeometry(geometry);
  impl_->throw_if_failed("geometry setup");
}

bool RayTracer::has_passing_surfaces() const {
  return !impl_->passing->empty();
}

Hit RayTracer::intersect(const Ray& ray) const {
  if (log_) log_->push_back({ray, false});
  RTCRayHit rayhit = to_rtc_ray_hit(ray);
#if BAKEGI_EMBREE_MAJOR >= 4
  rtcIntersect1(impl_->scene, &rayhit);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(impl_->scene, &context, &rayhit);
#endif
  return impl_->hit_of(ray, rayhit);
}

bool RayTracer::occluded(const Ray& ray) const {
  if (log_) log_->push_back({ray, true});
  RTCRay r = to_rtc_ray(ray);
#if BAKEGI_EMBREE_MAJOR >= 4
  rtcOccluded1(impl_->scene, &r);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(impl_->scene, &context, &r);
#endif
  // Embree marks an occluded ray by setting tfar to -inf.
  return r.tfar < 0.0f;
}

#if BAKEGI_EMBREE_MAJOR < 4
namespace {

// body(first, n) over [0, count) in pieces of n <= chunk (clamped to 1..kMaxStreamChunk), with
// `records` sized for the largest piece.
template <typename Record, typename Body>
void in_chunks(size_t count, size_t chunk, std::vector<Record>& records, const Body& body) {
  const size_t size = std::clamp<size_t>(chunk, 1, RayTracer::kMaxStreamChunk);
  records.resize(size);
  for (size_t first = 0; first < count; first += size) body(first, std::min(size, count - first));
}

}  // namespace
#endif

void RayTracer::intersect_stream(const Ray* rays, Hit* hits, size_t count, size_t chunk) const {
#if BAKEGI_EMBREE_MAJOR >= 4
  for (size_t i = 0; i < count; ++i) hits[i] = intersect(rays[i]);
#else
  std::vector<RTCRayHit> rayhits;
  in_chunks(count, chunk, rayhits, [&](size_t first, size_t n) {
    for (size_t i = 0; i < n; ++i) rayhits[i] = to_rtc_ray_hit(rays[first + i]);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1M(impl_->scene, &context, rayhits.data(), unsigned(n), sizeof(RTCRayHit));
    for (size_t i = 0; i < n; ++i) hits[first + i] = impl_->hit_of(rays[first + i], rayhits[i]);
  });
#endif
}

void RayTracer::occluded_stream(const Ray* rays, uint8_t* occluded, size_t count,
                                size_t chunk) const {
#if BAKEGI_EMBREE_MAJOR >= 4
  for (size_t i = 0; i < count; ++i) occluded[i] = this->occluded(rays[i]) ? 1 : 0;
#else
  std::vector<RTCRay> r;
  in_chunks(count, chunk, r, [&](size_t first, size_t n) {
    for (size_t i = 0; i < n; ++i) r[i] = to_rtc_ray(rays[first + i]);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1M(impl_->scene, &context, r.data(), unsigned(n), sizeof(RTCRay));
    for (size_t i = 0; i < n; ++i) occluded[first + i] = r[i].tfar < 0.0f ? 1 : 0;
  });
#endif
}

void RayTracer::intersect_many(const Ray* rays, Hit* hits, size_t count) const {
  // 16-wide packets, packets in parallel: the throughput Embree offers on this machine.
  constexpr size_t kWidth = 16;
  const size_t packets = (count + kWidth - 1) / kWidth;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, packets, 16), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t packet = range.begin(); packet != range.end(); ++packet) {
          const size_t first = packet * kWidth;
          const size_t n = std::min(kWidth, count - first);
          alignas(64) int valid[kWidth];
          RTCRayHit16 rayhit;
          for (size_t i = 0; i < kWidth; ++i) {
            valid[i] = i < n ? -1 : 0;
            const Ray& ray = rays[first + (i < n ? i : 0)];
            rayhit.ray.org_x[i] = ray.origin.x;
            rayhit.ray.org_y[i] = ray.origin.y;
            rayhit.ray.org_z[i] = ray.origin.z;
            rayhit.ray.dir_x[i] = ray.direction.x;
            rayhit.ray.dir_y[i] = ray.direction.y;
            rayhit.ray.dir_z[i] = ray.direction.z;
            rayhit.ray.tnear[i] = ray.tnear;
            rayhit.ray.tfar[i] = ray.tfar;
            rayhit.ray.time[i] = 0.0f;
            rayhit.ray.mask[i] = std::numeric_limits<unsigned>::max();
            rayhit.ray.id[i] = ray.seed;
            rayhit.ray.flags[i] = 0;
            rayhit.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            rayhit.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
          }
#if BAKEGI_EMBREE_MAJOR >= 4
          rtcIntersect16(valid, impl_->scene, &rayhit);
#else
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect16(valid, impl_->scene, &context, &rayhit);
#endif
          for (size_t i = 0; i < n; ++i) {
            Hit& hit = hits[first + i];
            hit = Hit{};
            if (rayhit.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
            hit.hit = true;
            hit.t = rayhit.ray.tfar[i];
            hit.triangle = impl_->triangle_of(rayhit.hit.geomID[i], rayhit.hit.primID[i]);
            hit.b1 = rayhit.hit.u[i];
            hit.b2 = rayhit.hit.v[i];
            hit.position = rays[first + i].origin + hit.t * rays[first + i].direction;
            hit.normal = glm::vec3(rayhit.hit.Ng_x[i], rayhit.hit.Ng_y[i], rayhit.hit.Ng_z[i]);
          }
        }
      });
}

size_t RayTracer::memory_bytes() const {
  return size_t(std::max<int64_t>(0, impl_->memory.load()));
}

}  // namespace bakegi
