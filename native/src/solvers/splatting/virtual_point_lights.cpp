#include "solvers/splatting/virtual_point_lights.h"

#include <algorithm>
#include <cmath>

#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

void VirtualPointLights::push(const glm::vec3& position, const glm::vec3& normal,
                              const glm::vec3& flux, float area) {
  positions.push_back(position);
  normals.push_back(normal);
  fluxes.push_back(flux);
  disk_areas.push_back(area / kPi);
}

namespace {

double map_luminance(const ReflectiveShadowMap& map) {
  double sum = 0.0;
  for (const RsmTexel& t : map.texels) sum += luminance(t.flux);
  return sum;
}

// How many VPLs each map gets: proportional to its reflected flux, at least one for a map
// with any, by largest remainders.
std::vector<uint32_t> share_out(const std::vector<ReflectiveShadowMap>& maps, uint32_t count) {
  std::vector<double> weight(maps.size());
  double total = 0.0;
  for (size_t m = 0; m < maps.size(); ++m) total += weight[m] = map_luminance(maps[m]);
  std::vector<uint32_t> shares(maps.size(), 0);
  if (!(total > 0.0)) return shares;
  std::vector<std::pair<double, size_t>> remainders;
  uint32_t given = 0;
  for (size_t m = 0; m < maps.size(); ++m) {
    if (!(weight[m] > 0.0)) continue;
    const double exact = weight[m] / total * count;
    shares[m] = std::max(1u, uint32_t(exact));
    given += shares[m];
    remainders.push_back({exact - std::floor(exact), m});
  }
  std::sort(remainders.rbegin(), remainders.rend());
  for (size_t i = 0; given < count && i < remainders.size(); ++i, ++given) {
    ++shares[remainders[i].second];
  }
  return shares;
}

// The paper's fixed grid: the map cut into about `share` blocks, one VPL per block
// with flux, at the texel with flux nearest the block's centre, carrying the block's flux
// and area.
void regular_vpls(const ReflectiveShadowMap& map, uint32_t share, VirtualPointLights& out) {
  if (share == 0 || map.texels.empty()) return;
  // Columns and rows of blocks in the map's proportions, about `share` blocks in all.
  const uint32_t columns = std::clamp(
      uint32_t(std::lround(std::sqrt(double(share) * map.width / map.height))), 1u, map.width);
  const uint32_t rows = std::clamp(uint32_t(std::lround(double(share) / columns)), 1u, map.height);
  const uint32_t block_w = (map.width + columns - 1) / columns;
  const uint32_t block_h = (map.height + rows - 1) / rows;
  for (uint32_t by = 0; by < map.height; by += block_h) {
    for (uint32_t bx = 0; bx < map.width; bx += block_w) {
      const uint32_t ex = std::min(map.width, bx + block_w);
      const uint32_t ey = std::min(map.height, by + block_h);
      glm::vec3 flux(0.0f);
      float area = 0.0f;
      const float cx = 0.5f * float(bx + ex - 1), cy = 0.5f * float(by + ey - 1);
      const RsmTexel* centre = nullptr;
      float best = 1e30f;
      for (uint32_t y = by; y < ey; ++y) {
        for (uint32_t x = bx; x < ex; ++x) {
          const RsmTexel& t = map.texels[size_t(y) * map.width + x];
          if (!(max_component(t.flux) > 0.0f)) continue;
          flux += t.flux;
          area += t.area;
          const float d = (float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy);
          if (d < best) best = d, centre = &t;
        }
      }
      if (!centre) continue;
      out.push(centre->position, centre->normal, flux, area);
      if (out.texel_begin.empty()) out.texel_begin.push_back(uint32_t(out.texels.size()));
      for (uint32_t y = by; y < ey; ++y) {
        for (uint32_t x = bx; x < ex; ++x) {
          const RsmTexel& t = map.texels[size_t(y) * map.width + x];
          if (max_component(t.flux) > 0.0f) out.texels.push_back(t);
        }
      }
      out.texel_begin.push_back(uint32_t(out.texels.size()));
    }
  }
}

// Texels drawn by luminance of reflected flux, systematically (one uniform offset), each
// carrying flux / (count p) and its area scaled alike.
void importance_vpls(const std::vector<ReflectiveShadowMap>& maps, uint32_t count,
                     VirtualPointLights& out) {
  std::vector<const RsmTexel*> texels;
  std::vector<double> cdf;
  double total = 0.0;
  for (const ReflectiveShadowMap& map : maps) {
    for (const RsmTexel& t : map.texels) {
      const double y = luminance(t.flux);
      if (!(y > 0.0)) continue;
      total += y;
      cdf.push_back(total);
      texels.push_back(&t);
    }
  }
  if (texels.empty() || count == 0) return;
  for (uint32_t k = 0; k < count; ++k) {
    const double u = (double(k) + 0.5) / double(count) * total;
    const size_t i = std::min(size_t(std::lower_bound(cdf.begin(), cdf.end(), u) - cdf.begin()),
                              texels.size() - 1);
    const RsmTexel& t = *texels[i];
    const double p = luminance(t.flux) / total;
    const float scale = float(1.0 / (double(count) * p));
    out.push(t.position, t.normal, t.flux * scale, t.area * scale);
  }
}

}  // namespace

VirtualPointLights select_vpls(const std::vector<ReflectiveShadowMap>& maps, uint32_t count,
                               VplSampling sampling) {
  VirtualPointLights vpls;
  if (sampling == VplSampling::kImportance) {
    importance_vpls(maps, count, vpls);
    return vpls;
  }
  // Blocks without flux (outside a spot's cone, past the scene's edge) give no VPL: ask
  // for more blocks until the count is reached (within 3%), at most a few times.
  uint32_t asked = count;
  for (int attempt = 0; attempt < 6; ++attempt) {
    vpls = VirtualPointLights{};
    vpls.texel_begin.clear();
    const std::vector<uint32_t> shares = share_out(maps, asked);
    for (size_t m = 0; m < maps.size(); ++m) regular_vpls(maps[m], shares[m], vpls);
    if (vpls.size() == 0 || vpls.size() * 100 >= size_t(count) * 97) break;
    asked = uint32_t(std::min<double>(double(asked) * count / double(vpls.size()) + 1.0, 1e7));
  }
  return vpls;
}

glm::vec3 vpl_term_over_pi(const VirtualPointLights& vpls, size_t v, const glm::vec3& position,
                           const glm::vec3& normal) {
  const glm::vec3 d = vpls.positions[v] - position;
  const float r2 = glm::dot(d, d);
  const float r = std::sqrt(r2);
  if (!(r > 0.0f)) return glm::vec3(0.0f);
  const float cos_receiver = std::max(0.0f, glm::dot(normal, d)) / r;
  const float cos_vpl = std::max(0.0f, -glm::dot(vpls.normals[v], d)) / r;
  constexpr float kInvPiSquared = 1.0f / (kPi * kPi);
  return vpls.fluxes[v] * (cos_receiver * cos_vpl * kInvPiSquared / (r2 + vpls.disk_areas[v]));
}

namespace {

// The VPLs [begin, end) at least sqrt(split2) radii of their surface away (all for 0).
glm::vec3 far_vpl_light(const VirtualPointLights& vpls, const glm::vec3& position,
                        const glm::vec3& normal, size_t begin, size_t end, float split2) {
  return sum_over_vpls(vpls, position, normal, begin, end,
                       [split2](float r2, float cr, float cv, float a) {
                         // cos_r cos_v / (r^2 + A/pi), both cosines' 1/r folded into r^2.
                         const bool far = r2 > 0.0f && r2 >= split2 * a;
                         return far ? cr * cv / (r2 * (r2 + a)) : 0.0f;
                       });
}

glm::vec3 texel_term_over_pi(const RsmTexel& t, const glm::vec3& position,
                             const glm::vec3& normal) {
  const glm::vec3 d = t.position - position;
  const float r2 = glm::dot(d, d);
  if (!(r2 > 0.0f)) return glm::vec3(0.0f);
  const float cr = std::max(0.0f, glm::dot(normal, d));
  const float cv = std::max(0.0f, -glm::dot(t.normal, d));
  return t.flux * (cr * cv / (r2 * (r2 + t.area / kPi)) / (kPi * kPi));
}

}  // namespace

glm::vec3 near_field_light(const VirtualPointLights& vpls, const glm::vec3& position,
                           const glm::vec3& normal, size_t begin, size_t end, float split) {
  if (vpls.texel_begin.size() != vpls.size() + 1 || !(split > 0.0f)) {
    return vpl_irradiance_over_pi(vpls, position, normal, begin, end);
  }
  const float split2 = split * split;
  // The far VPLs in one branch-free pass, then the texels of the few near ones.
  glm::vec3 sum = far_vpl_light(vpls, position, normal, begin, end, split2);
  for (size_t v = begin; v < end; ++v) {
    const glm::vec3 d = vpls.positions[v] - position;
    if (!(glm::dot(d, d) < split2 * vpls.disk_areas[v])) continue;
    for (uint32_t t = vpls.texel_begin[v]; t < vpls.texel_begin[v + 1]; ++t) {
      sum += texel_term_over_pi(vpls.texels[t], position, normal);
    }
  }
  return sum;
}

glm::vec3 vpl_irradiance_over_pi(const VirtualPointLights& vpls, const glm::vec3& position,
                                 const glm::vec3& normal, size_t begin, size_t end) {
  return far_vpl_light(vpls, position, normal, begin, end, 0.0f);
}

}  // namespace bakegi
