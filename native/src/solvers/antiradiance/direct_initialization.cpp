#include "solvers/antiradiance/direct_initialization.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/surface_point.h"
#include "scene/triangle_geometry.h"
#include "solvers/antiradiance/push_pull.h"
#include "util/error.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::antiradiance {

namespace {

constexpr size_t kPatchesPerBlock = 64;
// Patches per shadow-ray block: small, since each costs `samples` ray queries.
constexpr size_t kPatchesPerTracingBlock = 16;

}  // namespace

namespace {

void check_sizes(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                 size_t irradiance_count, const RadianceTables& tables) {
  if (tables.element_count() != hierarchy.element_count() ||
      tables.patch_count() != hierarchy.patch_count() || tables.bin_count() != bins.bin_count() ||
      irradiance_count != hierarchy.patch_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "direct initialization: sizes do not match the hierarchy");
  }
}

// The reflected direct light of every patch into its I_ex row. Emission is left out: the
// direct light (DirectLight) already samples emissive triangles with shadow rays, so light
// leaving an emitter reaches every receiver as *direct* light. Seeding it here as well
// transported it a second time, as indirect light (an emissive quad lighting a room gave
// 2.9x the path tracer's indirect light).
void seed_diffuse(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                  std::span<const glm::vec3> direct_irradiance, RadianceTables& tables) {
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  const int m = bins.bin_count();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        const Patch& patch = patches[p];
                        const glm::vec3 radiance =
                            patch.albedo * std::numbers::inv_pi_v<float> * direct_irradiance[p];
                        const glm::vec3 intensity = elements[patch.element].area * radiance;
                        const std::span<glm::vec3> exitant = tables.exitant(patch.element);
                        for (int j = 0; j < m; ++j) {
                          const float cosine = glm::dot(patch.normal, bins.direction(j));
                          exitant[size_t(j)] = std::max(cosine, 0.0f) * intensity;
                        }
                      }
                    });
}

// Adds a ⟨n|ω_j⟩₊ ρ_g G(ω_j) to the rows of the patches with a lobe.
void add_glossy(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                const DirectLightAtPatches& direct, RadianceTables& tables) {
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  std::vector<std::shared_ptr<const GlossyLobeTable>> keep_alive;
  const std::vector<const GlossyLobeTable*> glossy =
      glossy_tables_for_patches(patches, bins, keep_alive);
  const int m = bins.bin_count();
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        std::vector<glm::vec3> reflected, scratch;
        for (size_t p = block.begin(); p != block.end(); ++p) {
          const uint64_t begin = direct.binned_offsets[p], end = direct.binned_offsets[p + 1];
          if (glossy[p] == nullptr || begin == end) continue;
          const Patch& patch = patches[p];
          reflected.resize(size_t(m));
          reflect_direct_glossy(patch.normal, bins, *glossy[p],
                                std::span(direct.binned).subspan(begin, end - begin),
                                direct.glossy_reflectable[p], reflected, scratch);
          const float area = elements[patch.element].area;
          const std::span<glm::vec3> exitant = tables.exitant(patch.element);
          for (int j = 0; j < m; ++j) {
            const float cosine = glm::dot(patch.normal, bins.direction(j));
            if (cosine > 0.0f)
              exitant[size_t(j)] += (area * cosine) * patch.glossy * reflected[size_t(j)];
          }
        }
      });
}

void finish(const ElementHierarchy& hierarchy, RadianceTables& tables) {
  const std::span<glm::vec3> accumulated = tables.accumulated_irradiance();
  std::fill(accumulated.begin(), accumulated.end(), glm::vec3(0.0f));
  pull(hierarchy, tables);
}

// Where sample s of `samples` of a patch's direct light is taken: its centre, or on a merged
// patch a point of one of its triangles, chosen by area (stratified over the samples) with
// that triangle's normals. A merged patch thus holds its triangles' mean direct light: a sun
// stripe across part of a merged floor lights it in proportion, and a group whose centre is
// in shadow (or, on a curved group, whose area-weighted mean would lie inside the object) is
// not dark for it.
SurfacePoint sample_point(const Scene& scene, const ElementHierarchy& hierarchy,
                          const Patch& patch, const SurfacePoint& center, int64_t s,
                          int64_t samples, float area, RandomStream& rng) {
  if (patch.member_count == 0) return center;
  const std::span<const MemberTriangle> members = hierarchy.members(patch);
  const float target = (float(s) + rng.next_float()) / float(samples) * area;
  float running = 0.0f;
  const MemberTriangle* chosen = &members.back();
  for (const MemberTriangle& member : members) {
    running += member.area;
    if (running > target) {
      chosen = &member;
      break;
    }
  }
  const Triangle& t = scene.triangles[chosen->triangle];
  const glm::vec2 b = sample_triangle_barycentrics(rng.next_float(), rng.next_float());
  SurfacePoint x;
  x.position = at_barycentrics(chosen->corners, b);
  // A back-side patch gathers on the other side of the same triangles.
  const float side = patch.back_side ? -1.0f : 1.0f;
  x.geometric_normal = side * t.face_normal;
  // The shading normal where the point lies in its input triangle (a member may be a piece).
  const glm::vec3 shading = at_barycentrics(t.n, barycentrics_of(t.p, x.position));
  const float length = glm::length(shading);
  x.shading_normal = length > 1e-6f ? side * shading / length : x.geometric_normal;
  if (glm::dot(x.shading_normal, x.geometric_normal) <= 0.0f) x.shading_normal = x.geometric_normal;
  return x;
}

}  // namespace

void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       std::span<const glm::vec3> direct_irradiance, RadianceTables& tables) {
  check_sizes(hierarchy, bins, direct_irradiance.size(), tables);
  seed_diffuse(hierarchy, bins, direct_irradiance, tables);
  finish(hierarchy, tables);
}

void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       const DirectLightAtPatches& direct, RadianceTables& tables) {
  check_sizes(hierarchy, bins, direct.irradiance.size(), tables);
  if (direct.binned_offsets.size() != hierarchy.patch_count() + 1 ||
      direct.glossy_reflectable.size() != hierarchy.patch_count() ||
      direct.binned_offsets.back() != direct.binned.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "direct initialization: the binned direct light does not match the hierarchy");
  }
  for (size_t p = 0; p < hierarchy.patch_count(); ++p) {
    if (direct.binned_offsets[p] > direct.binned_offsets[p + 1]) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "direct initialization: the binned light's offsets decrease");
    }
  }
  for (const BinnedIrradiance& e : direct.binned) {
    if (e.bin >= bins.bin_count()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "direct initialization: bin out of range");
    }
  }
  seed_diffuse(hierarchy, bins, direct.irradiance, tables);
  add_glossy(hierarchy, bins, direct, tables);
  finish(hierarchy, tables);
}

DirectLightAtPatches direct_light_at_patches(const ElementHierarchy& hierarchy,
                                             const DirectionalBins& bins, const DirectLight& direct,
                                             int64_t samples, uint64_t seed, JobContext& context) {
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  std::vector<std::shared_ptr<const GlossyLobeTable>> keep_alive;
  const std::vector<const GlossyLobeTable*> glossy =
      glossy_tables_for_patches(patches, bins, keep_alive);
  DirectLightAtPatches result;
  result.irradiance.assign(patches.size(), glm::vec3(0.0f));
  result.glossy_reflectable.assign(patches.size(), glm::vec3(0.0f));
  std::vector<std::vector<BinnedIrradiance>> binned(patches.size());
  const int m = bins.bin_count();
  if (samples > 0) {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerTracingBlock),
        [&](const tbb::blocked_range<size_t>& block) {
          uint64_t rays = 0;
          std::vector<glm::dvec3> per_bin;
          std::vector<std::pair<glm::vec3, glm::vec3>> terms;  // (direction, irradiance)
          for (size_t p = block.begin(); p != block.end(); ++p) {
            context.throw_if_cancelled();
            const Patch& patch = patches[p];
            const SurfacePoint x{elements[patch.element].center, patch.shading_normal,
                                 patch.normal};
            glm::dvec3 sum(0.0);
            if (glossy[p] == nullptr) {
              // The same loop as direct_irradiance_at_patches.
              for (int64_t s = 0; s < samples; ++s) {
                RandomStream rng = sample_stream(seed, p, uint64_t(s));
                const SurfacePoint xs = sample_point(direct.scene(), hierarchy, patch, x, s,
                                                     samples, elements[patch.element].area, rng);
                const glm::vec3 value = direct.irradiance_sample(xs, rng, rays);
                if (is_finite(value)) sum += glm::dvec3(value);
              }
              result.irradiance[p] = glm::vec3(sum / double(samples));
              continue;
            }
            const GlossyLobeTable& table = *glossy[p];
            per_bin.assign(size_t(m), glm::dvec3(0.0));
            glm::dvec3 reflectable(0.0);
            for (int64_t s = 0; s < samples; ++s) {
              RandomStream rng = sample_stream(seed, p, uint64_t(s));
              terms.clear();
              const SurfacePoint xs = sample_point(direct.scene(), hierarchy, patch, x, s,
                                                   samples, elements[patch.element].area, rng);
              const glm::vec3 value = direct.irradiance_sample_terms(
                  xs, rng, rays, [&](const glm::vec3& direction, const glm::vec3& irradiance) {
                    terms.emplace_back(direction, irradiance);
                  });
              // A non-finite sample would poison the patch and everything it lights.
              if (!is_finite(value)) continue;
              sum += glm::dvec3(value);
              for (const auto& [direction, irradiance] : terms) {
                // The lobe lives on the face normal (as in the local pass): light from behind
                // it (possible with a tilted shading normal) is not reflected.
                const float mu = glm::dot(patch.normal, direction);
                if (!(mu > 0.0f)) continue;
                // Bins hold the direction light travels: away from the light.
                per_bin[size_t(bins.bin_of(-direction))] += glm::dvec3(irradiance);
                reflectable += double(table.directional_albedo(mu)) * glm::dvec3(irradiance);
              }
            }
            result.irradiance[p] = glm::vec3(sum / double(samples));
            result.glossy_reflectable[p] = glm::vec3(reflectable / double(samples));
            for (int l = 0; l < m; ++l) {
              const glm::dvec3& e = per_bin[size_t(l)];
              if (e.x != 0.0 || e.y != 0.0 || e.z != 0.0) {
                binned[p].push_back({uint16_t(l), glm::vec3(e / double(samples))});
              }
            }
          }
          context.report().add_count("rays", rays);
        });
  }
  result.binned_offsets.assign(patches.size() + 1, 0);
  for (size_t p = 0; p < patches.size(); ++p) {
    result.binned_offsets[p + 1] = result.binned_offsets[p] + binned[p].size();
  }
  result.binned.reserve(result.binned_offsets.back());
  for (std::vector<BinnedIrradiance>& entries : binned) {
    result.binned.insert(result.binned.end(), entries.begin(), entries.end());
    std::vector<BinnedIrradiance>().swap(entries);
  }
  return result;
}

std::vector<glm::vec3> direct_irradiance_at_patches(const ElementHierarchy& hierarchy,
                                                    const DirectLight& direct, int64_t samples,
                                                    uint64_t seed, JobContext& context) {
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  std::vector<glm::vec3> irradiance(patches.size(), glm::vec3(0.0f));
  if (samples <= 0) return irradiance;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerTracingBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        uint64_t rays = 0;
        for (size_t p = block.begin(); p != block.end(); ++p) {
          context.throw_if_cancelled();
          const Patch& patch = patches[p];
          const SurfacePoint x{elements[patch.element].center, patch.shading_normal, patch.normal};
          glm::dvec3 sum(0.0);
          for (int64_t s = 0; s < samples; ++s) {
            RandomStream rng = sample_stream(seed, p, uint64_t(s));
            const SurfacePoint xs = sample_point(direct.scene(), hierarchy, patch, x, s, samples,
                                                 elements[patch.element].area, rng);
            const glm::vec3 value = direct.irradiance_sample(xs, rng, rays);
            // A non-finite sample would poison the patch and everything it lights.
            if (std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z)) {
              sum += glm::dvec3(value);
            }
          }
          irradiance[p] = glm::vec3(sum / double(samples));
        }
        context.report().add_count("rays", rays);
      });
  return irradiance;
}

}  // namespace bakegi::antiradiance
