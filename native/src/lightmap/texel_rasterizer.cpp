#include "lightmap/texel_rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "util/error.h"

namespace bakegi {

namespace {

// A convex polygon in pixel units: a triangle clipped by up to four texel edges.
struct Polygon {
  std::array<glm::dvec2, 8> v;
  int count = 0;
};

// Sutherland-Hodgman against the half plane where axis coordinate `axis` is >= bound
// (sign = +1) or <= bound (sign = -1).
Polygon clip(const Polygon& in, int axis, double bound, double sign) {
  Polygon out;
  for (int i = 0; i < in.count; ++i) {
    const glm::dvec2& a = in.v[i];
    const glm::dvec2& b = in.v[(i + 1) % in.count];
    const double da = sign * (a[axis] - bound), db = sign * (b[axis] - bound);
    if (da >= 0) out.v[out.count++] = a;
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      glm::dvec2 p = a + t * (b - a);
      p[axis] = bound;  // exactly on the edge, whatever the rounding
      out.v[out.count++] = p;
    }
  }
  return out;
}

double area(const Polygon& polygon) {
  double twice = 0;
  for (int i = 0; i < polygon.count; ++i) {
    const glm::dvec2& a = polygon.v[i];
    const glm::dvec2& b = polygon.v[(i + 1) % polygon.count];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * std::abs(twice);
}

// Closest point of segment ab to p.
glm::dvec2 closest_on_segment(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
  const glm::dvec2 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return a + t * ab;
}

// Barycentrics (b0, b1, b2) of p in the (non-degenerate) triangle t; p is moved to the
// closest point of the triangle first when it lies outside (inside = false).
glm::dvec3 clamped_barycentrics(const glm::dvec2& p, const glm::dvec2 t[3], bool& inside) {
  const double twice_area =
      (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
  auto barycentrics = [&](const glm::dvec2& q) {
    const double b1 =
        ((q.x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (q.y - t[0].y)) / twice_area;
    const double b2 =
        ((t[1].x - t[0].x) * (q.y - t[0].y) - (q.x - t[0].x) * (t[1].y - t[0].y)) / twice_area;
    return glm::dvec3(1.0 - b1 - b2, b1, b2);
  };
  const glm::dvec3 b = barycentrics(p);
  inside = b.x >= 0 && b.y >= 0 && b.z >= 0;
  if (inside) return b;
  glm::dvec2 best = p;
  double best_distance = INFINITY;
  for (int e = 0; e < 3; ++e) {
    const glm::dvec2 q = closest_on_segment(p, t[e], t[(e + 1) % 3]);
    const double d = glm::dot(q - p, q - p);
    if (d < best_distance) best_distance = d, best = q;
  }
  const glm::dvec3 c = glm::max(barycentrics(best), glm::dvec3(0.0));
  return c / (c.x + c.y + c.z);  // rounding may leave -1e-17; keep it a convex combination
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

size_t TexelSamples::covered_texels() const {
  return size_t(std::count(covered.begin(), covered.end(), uint8_t(1)));
}

uint64_t max_texel_samples(const std::vector<LightmapTriangle>& triangles, uint32_t width,
                           uint32_t height) {
  double total = 0.0;
  for (const LightmapTriangle& tri : triangles) {
    glm::dvec2 t[3];
    for (int k = 0; k < 3; ++k) {
      // Parts outside [0,1]^2 are clipped away; clamping keeps the bound an upper bound.
      t[k] = glm::clamp(glm::dvec2(tri.uv[k]), 0.0, 1.0) * glm::dvec2(width, height);
    }
    const double area = 0.5 * std::abs((t[1].x - t[0].x) * (t[2].y - t[0].y) -
                                       (t[2].x - t[0].x) * (t[1].y - t[0].y));
    const double perimeter =
        glm::length(t[1] - t[0]) + glm::length(t[2] - t[1]) + glm::length(t[0] - t[2]);
    const glm::dvec2 lo = glm::min(t[0], glm::min(t[1], t[2]));
    const glm::dvec2 hi = glm::max(t[0], glm::max(t[1], t[2]));
    const double box =
        (std::floor(hi.x) - std::floor(lo.x) + 1) * (std::floor(hi.y) - std::floor(lo.y) + 1);
    const double bound = std::min(area + 2.0 * std::sqrt(2.0) * perimeter + 4.0, box);
    if (std::isfinite(bound)) total += bound;
  }
  return uint64_t(std::ceil(total));
}

TexelSamples rasterize_texels(const std::vector<LightmapTriangle>& triangles, uint32_t width,
                              uint32_t height, uint32_t object_id, const CancelFlag* cancel) {
  if (width == 0 || height == 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap size " + std::to_string(width) + " x " +
                                                   std::to_string(height) + " is empty");
  }
  TexelSamples out;
  out.width = width;
  out.height = height;
  out.covered.assign(size_t(width) * height, 0);
  // UV triangles smaller than this many texels carry no area worth a sample (and their
  // barycentrics would be noise).
  constexpr double kMinPixelArea = 1e-9;

  for (size_t index = 0; index < triangles.size(); ++index) {
    const LightmapTriangle& tri = triangles[index];
    for (int k = 0; k < 3; ++k) {
      if (!finite(tri.p[k]) || !std::isfinite(tri.uv[k].x) || !std::isfinite(tri.uv[k].y)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap triangle " + std::to_string(index) +
                                                       ": position or UV is not finite");
      }
    }
    const glm::dvec3 cross =
        glm::cross(glm::dvec3(tri.p[1] - tri.p[0]), glm::dvec3(tri.p[2] - tri.p[0]));
    const double cross_length = glm::length(cross);
    if (!(cross_length > 0)) {
      ++out.skipped_degenerate_geometry;
      continue;
    }
    const glm::vec3 face_normal = glm::vec3(cross / cross_length);
    glm::dvec2 t[3];
    for (int k = 0; k < 3; ++k) t[k] = glm::dvec2(tri.uv[k]) * glm::dvec2(width, height);
    const double twice_area =
        (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
    if (!(std::abs(twice_area) > 2 * kMinPixelArea)) {
      ++out.skipped_degenerate_uv;
      continue;
    }
    glm::vec3 normals[3];
    for (int k = 0; k < 3; ++k) {
      const float length = glm::length(tri.n[k]);
      normals[k] = finite(tri.n[k]) && length > 1e-20f ? tri.n[k] / length : face_normal;
    }
    const glm::dvec2 lo = glm::min(t[0], glm::min(t[1], t[2]));
    const glm::dvec2 hi = glm::max(t[0], glm::max(t[1], t[2]));
    // Clamped in double first: UVs far outside the map must not overflow the int casts.
    const auto first_texel = [](double lo, uint32_t size) {
      return int(std::clamp(std::floor(lo), 0.0, double(size)));
    };
    const auto last_texel = [](double hi, uint32_t size) {
      return int(std::clamp(std::ceil(hi), 0.0, double(size))) - 1;
    };
    const int x0 = first_texel(lo.x, width), y0 = first_texel(lo.y, height);
    const int x1 = last_texel(hi.x, width), y1 = last_texel(hi.y, height);
    for (int y = y0; y <= y1; ++y) {
      throw_if_cancelled(cancel, "rasterizing the lightmap texels");
      // Clip the triangle to the row first: the per-texel clip then needs only x.
      Polygon row;
      row.count = 3;
      for (int k = 0; k < 3; ++k) row.v[k] = t[k];
      row = clip(clip(row, 1, y, +1), 1, y + 1, -1);
      if (row.count < 3) continue;
      for (int x = x0; x <= x1; ++x) {
        const Polygon cell = clip(clip(row, 0, x, +1), 0, x + 1, -1);
        if (cell.count < 3) continue;
        const double covered = area(cell);  // texel area is 1 pixel
        bool centre_inside = false;
        const glm::dvec3 b = clamped_barycentrics(glm::dvec2(x + 0.5, y + 0.5), t, centre_inside);
        // Overlaps of rounding-error size (a triangle edge on the texel's border) are not
        // coverage; a centre inside the triangle always is.
        if (!(covered > kMinPixelArea) && !centre_inside) continue;
        const glm::vec3 position = glm::vec3(
            b.x * glm::dvec3(tri.p[0]) + b.y * glm::dvec3(tri.p[1]) + b.z * glm::dvec3(tri.p[2]));
        glm::vec3 normal =
            float(b.x) * normals[0] + float(b.y) * normals[1] + float(b.z) * normals[2];
        const float normal_length = glm::length(normal);
        normal = normal_length > 1e-6f ? normal / normal_length : face_normal;
        const uint32_t texel = uint32_t(y) * width + uint32_t(x);
        out.points.positions.push_back(position);
        out.points.normals.push_back(normal);
        out.points.object_ids.push_back(object_id);
        out.face_normals.push_back(face_normal);
        out.texel.push_back(texel);
        out.weight.push_back(float(std::min(covered, 1.0)));
        out.covered[texel] = 1;
      }
    }
  }
  return out;
}

void keep_samples(TexelSamples& samples, const std::vector<bool>& keep) {
  if (keep.size() != samples.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "keep_samples: mask size differs from the sample count");
  }
  size_t kept = 0;
  std::fill(samples.covered.begin(), samples.covered.end(), uint8_t(0));
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!keep[i]) continue;
    samples.points.positions[kept] = samples.points.positions[i];
    samples.points.normals[kept] = samples.points.normals[i];
    samples.points.object_ids[kept] = samples.points.object_ids[i];
    samples.face_normals[kept] = samples.face_normals[i];
    samples.texel[kept] = samples.texel[i];
    samples.weight[kept] = samples.weight[i];
    samples.covered[samples.texel[i]] = 1;
    ++kept;
  }
  samples.points.positions.resize(kept);
  samples.points.normals.resize(kept);
  samples.points.object_ids.resize(kept);
  samples.face_normals.resize(kept);
  samples.texel.resize(kept);
  samples.weight.resize(kept);
}

void append_samples(TexelSamples& into, TexelSamples&& more) {
  if (into.width != more.width || into.height != more.height) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "cannot merge lightmap samples of " + std::to_string(more.width) + " x " +
                    std::to_string(more.height) + " texels into a " + std::to_string(into.width) +
                    " x " + std::to_string(into.height) + " lightmap");
  }
  if (into.covered.size() != more.covered.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "append_samples: coverage masks differ in size");
  }
  // Reserve everything first: if an allocation fails, `into` is left as it was. Capacity
  // grows geometrically: an atlas collects one object after another (Sponza: 170), and an
  // exact reserve would copy the whole atlas at every object.
  const auto reserve = [](auto& to, const auto& from) {
    const size_t needed = to.size() + from.size();
    if (needed > to.capacity()) to.reserve(std::max(needed, to.capacity() + to.capacity() / 2));
  };
  reserve(into.points.positions, more.points.positions);
  reserve(into.points.normals, more.points.normals);
  reserve(into.points.object_ids, more.points.object_ids);
  reserve(into.face_normals, more.face_normals);
  reserve(into.texel, more.texel);
  reserve(into.weight, more.weight);
  const auto append = [](auto& to, const auto& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  append(into.points.positions, more.points.positions);
  append(into.points.normals, more.points.normals);
  append(into.points.object_ids, more.points.object_ids);
  append(into.face_normals, more.face_normals);
  append(into.texel, more.texel);
  append(into.weight, more.weight);
  for (size_t t = 0; t < into.covered.size(); ++t) into.covered[t] |= more.covered[t];
  into.skipped_degenerate_uv += more.skipped_degenerate_uv;
  into.skipped_degenerate_geometry += more.skipped_degenerate_geometry;
}

}  // namespace bakegi
