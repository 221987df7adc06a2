#include "solvers/splatting/reflective_shadow_map.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/area_light.h"
#include "lights/spot_light.h"
#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// What one texel's ray carries before it lands: the power through the texel (W, RGB) and
// how the ray's footprint grows, by solid angle (rays from a point) or by the area of the
// texel on a plane across parallel rays.
struct TexelRay {
  Ray ray;  // unit direction
  glm::vec3 power{0.0f};
  float solid_angle = 0.0f;  // sr; 0 for parallel rays
  float plane_area = 0.0f;   // m^2 across parallel rays
};

// Grazing hits stand for a long strip of surface; the cap keeps one texel's area finite
// (the flux it carries is exact either way).
constexpr float kMinFootprintCosine = 0.1f;

// Traces a view's rays into its texels.
void trace_view(const Scene& scene, const RayTracer& tracer, const std::vector<TexelRay>& rays,
                ReflectiveShadowMap& map) {
  map.texels.assign(rays.size(), RsmTexel{});
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, rays.size(), 256),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const TexelRay& r = rays[i];
          if (!(max_component(r.power) > 0.0f)) continue;
          const Hit hit = tracer.intersect(r.ray);
          if (!hit.hit) continue;
          const Triangle& triangle = scene.triangles[hit.triangle];
          const SurfacePoint x = surface_at_hit(scene, hit, r.ray.direction);
          RsmTexel& texel = map.texels[i];
          texel.position = x.position;
          texel.normal = x.shading_normal;
          texel.albedo = scene.albedo_at(triangle, hit.b1, hit.b2);
          texel.flux = texel.albedo * r.power;
          const float cosine = std::max(std::abs(glm::dot(r.ray.direction, x.geometric_normal)),
                                        kMinFootprintCosine);
          texel.area =
              (r.solid_angle > 0.0f ? r.solid_angle * hit.t * hit.t : r.plane_area) / cosine;
        }
      });
}

ReflectiveShadowMap make_map(uint32_t light, const char* kind, uint32_t width, uint32_t height) {
  ReflectiveShadowMap map;
  map.light = light;
  map.kind = kind;
  map.width = width;
  map.height = height;
  return map;
}

// A perspective view from `origin` through a square of half-size `half_extent` on the plane
// at unit distance along `axis` (tangent and bitangent span it); `intensity(direction)` is
// the light's radiant intensity (W/sr) along a unit direction.
template <typename Intensity>
std::vector<TexelRay> perspective_rays(const glm::vec3& origin, const Frame& frame,
                                       float half_extent, uint32_t n, Intensity&& intensity) {
  std::vector<TexelRay> rays(size_t(n) * n);
  const float texel = 2.0f * half_extent / float(n);
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const float u = -half_extent + (float(i) + 0.5f) * texel;
      const float v = -half_extent + (float(j) + 0.5f) * texel;
      const glm::vec3 through = frame.normal + frame.tangent * u + frame.bitangent * v;
      const float length = glm::length(through);
      TexelRay& r = rays[size_t(j) * n + i];
      r.ray.origin = origin;
      r.ray.direction = through / length;
      // A texel of area dA on the unit plane subtends dA cos^3 = dA / length^3.
      r.solid_angle = texel * texel / (length * length * length);
      r.power = intensity(r.ray.direction) * r.solid_angle;
    }
  }
  return rays;
}

// A cosine-weighted hemisphere view from a point of an emitter of radiance `radiance` that
// stands for `area` m^2 of it: every texel carries the same power, L * area * pi / n^2.
std::vector<TexelRay> hemisphere_rays(const glm::vec3& origin, const glm::vec3& normal,
                                      const glm::vec3& radiance, float area, uint32_t n) {
  std::vector<TexelRay> rays(size_t(n) * n);
  const Frame frame(normal);
  const float measure = kPi / float(n * n);  // projected solid angle per texel
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const glm::vec3 local =
          sample_cosine_hemisphere((float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n));
      TexelRay& r = rays[size_t(j) * n + i];
      r.ray.origin = origin;
      r.ray.direction = glm::normalize(frame.to_world(local));
      r.solid_angle = measure / std::max(local.z, 0.05f);
      r.power = radiance * (area * measure);
    }
  }
  return rays;
}

// Parallel rays along `direction` over the scene's bounds, each texel carrying
// irradiance * its area on the plane across the rays.
std::vector<TexelRay> parallel_rays(const Scene& scene, const glm::vec3& direction,
                                    const glm::vec3& irradiance, uint32_t n) {
  const Frame frame(direction);
  const glm::vec3 center = 0.5f * (scene.bounds_min + scene.bounds_max);
  const float radius = 0.5f * scene.extent() * 1.01f + 1e-6f;
  std::vector<TexelRay> rays(size_t(n) * n);
  const float texel = 2.0f * radius / float(n);
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const float u = -radius + (float(i) + 0.5f) * texel;
      const float v = -radius + (float(j) + 0.5f) * texel;
      TexelRay& r = rays[size_t(j) * n + i];
      r.ray.origin = center + frame.tangent * u + frame.bitangent * v - direction * (2.0f * radius);
      r.ray.direction = direction;
      r.plane_area = texel * texel;
      r.power = irradiance * r.plane_area;
    }
  }
  return rays;
}

uint32_t spot_side(uint32_t resolution, uint32_t spots) {
  const uint32_t per_side = uint32_t(std::ceil(std::sqrt(double(spots))));
  return std::max(1u, resolution / per_side);
}

void add_point_light(const Scene& scene, const RayTracer& tracer, uint32_t index,
                     const Light& light, const RsmOptions& options,
                     std::vector<ReflectiveShadowMap>& maps) {
  const SpotCone cone = light.type == BAKEGI_LIGHT_SPOT ? SpotCone(light) : SpotCone();
  const auto intensity = [&](const glm::vec3& d) { return light.color * cone.attenuation(d); };
  const float half_angle = 0.5f * light.spot_size;
  if (light.type == BAKEGI_LIGHT_SPOT && half_angle < glm::radians(60.0f)) {
    const glm::vec3 axis = glm::normalize(light.direction);
    ReflectiveShadowMap map = make_map(index, "spot", options.resolution, options.resolution);
    trace_view(scene, tracer,
               perspective_rays(light.position, Frame(axis), std::tan(half_angle),
                                options.resolution, intensity),
               map);
    maps.push_back(std::move(map));
    return;
  }
  // Point lights and wide spots: a cube of six faces holding 1.5 x resolution^2 texels.
  const uint32_t n = std::max(1u, options.resolution / 2);
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const glm::vec3& axis : axes) {
    ReflectiveShadowMap map = make_map(index, "point face", n, n);
    trace_view(scene, tracer, perspective_rays(light.position, Frame(axis), 1.0f, n, intensity),
               map);
    maps.push_back(std::move(map));
  }
}

void add_area_light(const Scene& scene, const RayTracer& tracer, uint32_t index, const Light& light,
                    const RsmOptions& options, std::vector<ReflectiveShadowMap>& maps) {
  const AreaLight area_light(light);
  const uint32_t per_side = uint32_t(std::ceil(std::sqrt(double(options.spots))));
  const uint32_t n = spot_side(options.resolution, options.spots);
  const float share = area_light.area() / float(per_side * per_side);
  for (uint32_t sj = 0; sj < per_side; ++sj) {
    for (uint32_t si = 0; si < per_side; ++si) {
      const glm::vec3 point = area_light.point_at((float(si) + 0.5f) / float(per_side),
                                                  (float(sj) + 0.5f) / float(per_side));
      const glm::vec3 origin = point + area_light.normal() * options.ray_epsilon;
      ReflectiveShadowMap map = make_map(index, "area spot", n, n);
      trace_view(scene, tracer,
                 hemisphere_rays(origin, area_light.normal(), area_light.radiance(), share, n),
                 map);
      maps.push_back(std::move(map));
    }
  }
}

void add_emissive_meshes(const Scene& scene, const RayTracer& tracer, const RsmOptions& options,
                         std::vector<ReflectiveShadowMap>& maps) {
  // Spots drawn over the emitters by power (area x mean emission x sides), systematically, so
  // that every emitter with a share of at least 1/spots gets one.
  std::vector<double> cdf;
  std::vector<uint32_t> emitters;
  double total = 0.0;
  for (uint32_t t : scene.emissive_triangles) {
    const Triangle& triangle = scene.triangles[t];
    const Material& material = scene.material_of(triangle);
    const double power = double(triangle.area) * luminance(material.emission) *
                         (material.emission_two_sided ? 2.0 : 1.0);
    if (!(power > 0.0)) continue;
    total += power;
    cdf.push_back(total);
    emitters.push_back(t);
  }
  if (emitters.empty()) return;
  const uint32_t count = std::max(1u, options.spots);
  const uint32_t n = spot_side(options.resolution, options.spots);
  const uint32_t light_index = uint32_t(scene.description.lights.size());
  for (uint32_t k = 0; k < count; ++k) {
    const double u = (double(k) + 0.5) / double(count) * total;
    const size_t e = std::min(size_t(std::lower_bound(cdf.begin(), cdf.end(), u) - cdf.begin()),
                              emitters.size() - 1);
    const Triangle& triangle = scene.triangles[emitters[e]];
    const Material& material = scene.material_of(triangle);
    const double probability = (cdf[e] - (e > 0 ? cdf[e - 1] : 0.0)) / total;
    // A point inside the triangle from the golden-ratio sequence, different per spot.
    const float g1 = float(std::fmod(0.5 + 0.7548776662466927 * k, 1.0));
    const float g2 = float(std::fmod(0.5 + 0.5698402909980532 * k, 1.0));
    const glm::vec2 b = sample_triangle_barycentrics(g1, g2);
    const glm::vec3 point =
        triangle.p[0] * (1.0f - b.x - b.y) + triangle.p[1] * b.x + triangle.p[2] * b.y;
    const bool two_sided = material.emission_two_sided;
    const glm::vec3 normal =
        two_sided && (k % 2 == 1) ? -triangle.face_normal : triangle.face_normal;
    const float share =
        float(double(triangle.area) / (double(count) * probability)) * (two_sided ? 2.0f : 1.0f);
    ReflectiveShadowMap map = make_map(light_index, "emissive spot", n, n);
    trace_view(scene, tracer,
               hemisphere_rays(point + normal * options.ray_epsilon, normal,
                               scene.emission_at(triangle, b.x, b.y), share, n),
               map);
    maps.push_back(std::move(map));
  }
}

void add_world(const Scene& scene, const RayTracer& tracer, const RsmOptions& options,
               std::vector<ReflectiveShadowMap>& maps) {
  const glm::vec3 radiance = scene.description.world_radiance;
  if (!(max_component(radiance) > 0.0f)) return;
  const uint32_t count = std::max(1u, options.spots);
  const uint32_t n = spot_side(options.resolution, options.spots);
  const uint32_t light_index = uint32_t(scene.description.lights.size()) + 1;
  // Directions of arrival on a Fibonacci sphere, each standing for 4 pi / count sr.
  const float golden = kPi * (3.0f - std::sqrt(5.0f));
  for (uint32_t k = 0; k < count; ++k) {
    const float z = 1.0f - 2.0f * (float(k) + 0.5f) / float(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const glm::vec3 direction(r * std::cos(golden * k), r * std::sin(golden * k), z);
    ReflectiveShadowMap map = make_map(light_index, "world", n, n);
    trace_view(scene, tracer,
               parallel_rays(scene, direction, radiance * (4.0f * kPi / float(count)), n), map);
    maps.push_back(std::move(map));
  }
}

}  // namespace

std::vector<ReflectiveShadowMap> render_reflective_shadow_maps(const Scene& scene,
                                                               const RayTracer& tracer,
                                                               const RsmOptions& options) {
  std::vector<ReflectiveShadowMap> maps;
  const auto& lights = scene.description.lights;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    switch (light.type) {
      case BAKEGI_LIGHT_POINT:
      case BAKEGI_LIGHT_SPOT:
        add_point_light(scene, tracer, i, light, options, maps);
        break;
      case BAKEGI_LIGHT_SUN: {
        ReflectiveShadowMap map = make_map(i, "sun", options.resolution, options.resolution);
        trace_view(
            scene, tracer,
            parallel_rays(scene, glm::normalize(light.direction), light.color, options.resolution),
            map);
        maps.push_back(std::move(map));
        break;
      }
      case BAKEGI_LIGHT_AREA:
        add_area_light(scene, tracer, i, light, options, maps);
        break;
      default:
        break;
    }
  }
  add_emissive_meshes(scene, tracer, options, maps);
  add_world(scene, tracer, options, maps);
  return maps;
}

glm::dvec3 total_reflected_flux(const std::vector<ReflectiveShadowMap>& maps) {
  glm::dvec3 total(0.0);
  for (const ReflectiveShadowMap& map : maps) {
    for (const RsmTexel& texel : map.texels) total += glm::dvec3(texel.flux);
  }
  return total;
}

}  // namespace bakegi
