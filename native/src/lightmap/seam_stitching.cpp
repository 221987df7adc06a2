#include "lightmap/seam_stitching.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"

namespace bakegi {

namespace {

// The texels a bilinear lookup reads and their weights (duplicates merged where the border
// clamps two taps onto one texel).
struct Footprint {
  uint32_t texel[4];
  float weight[4];
  int count = 0;
};

// One axis of the lookup: the lower texel, the upper one and the upper one's weight.
struct Taps {
  uint32_t low, high;
  float high_weight;
};

Taps axis_taps(float coordinate, uint32_t size) {
  // Texel centres at (i + 0.5) / size; clamped in double so far-off UVs cannot overflow.
  const double x = std::clamp(double(coordinate) * size - 0.5, 0.0, double(size - 1));
  const uint32_t low = std::min(uint32_t(x), size - 1);
  const uint32_t high = std::min(low + 1, size - 1);
  return {low, high, float(x - low)};
}

Footprint footprint(uint32_t width, uint32_t height, glm::vec2 uv) {
  const Taps x = axis_taps(uv.x, width), y = axis_taps(uv.y, height);
  Footprint f;
  const auto add = [&](uint32_t tx, uint32_t ty, float w) {
    const uint32_t texel = ty * width + tx;
    for (int i = 0; i < f.count; ++i) {
      if (f.texel[i] == texel) {
        f.weight[i] += w;
        return;
      }
    }
    f.texel[f.count] = texel;
    f.weight[f.count++] = w;
  };
  add(x.low, y.low, (1 - x.high_weight) * (1 - y.high_weight));
  add(x.high, y.low, x.high_weight * (1 - y.high_weight));
  add(x.low, y.high, (1 - x.high_weight) * y.high_weight);
  add(x.high, y.high, x.high_weight * y.high_weight);
  return f;
}

glm::vec3 read(const RgbImage& image, const Footprint& f) {
  glm::vec3 value(0.0f);
  for (int i = 0; i < f.count; ++i) value += f.weight[i] * image.pixels[f.texel[i]];
  return value;
}

// A seam side at one point: the footprint's texels that may move (unfilled ones keep 0 and
// drop out), and whether the side reads baked light.
struct Side {
  Footprint all;
  Footprint movable;
  bool baked = false;
};

// A side whose filled texels weigh less than this reads mostly the zeros around the baked
// texels (a hole left by inside-geometry rejection wider than the padding, or the gutter
// at padding 0): what it reads says nothing about the light there, and matching it would
// pull the other side toward black and multiply the step on its few filled texels.
constexpr float kMinFilledWeight = 0.5f;
// A side whose covered texels weigh less than this reads only values dilated from
// elsewhere: its chart's texels there were rejected as inside geometry (hidden), and
// stitching it would only disturb the visible texels it shares with other seams. A point
// on a chart's edge always has covered weight on its own side: the rasterizer covers
// every texel the chart touches, and the footprint weighs the nearest one at least 1/4.
constexpr float kMinCoveredWeight = 0.25f;

Side side(const RgbImage& image, const std::vector<uint8_t>& covered,
          const std::vector<uint8_t>& filled, glm::vec2 uv) {
  Side s;
  s.all = footprint(image.width, image.height, uv);
  float weight = 0, covered_weight = 0;
  for (int i = 0; i < s.all.count; ++i) {
    if (covered[s.all.texel[i]]) covered_weight += s.all.weight[i];
    if (!filled[s.all.texel[i]] || !(s.all.weight[i] > 0)) continue;
    s.movable.texel[s.movable.count] = s.all.texel[i];
    s.movable.weight[s.movable.count++] = s.all.weight[i];
    weight += s.all.weight[i];
  }
  s.baked = weight >= kMinFilledWeight && covered_weight >= kMinCoveredWeight;
  return s;
}

float largest_component(const glm::vec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

// A seam point's constraint "side A reads what side B reads" on the texels that may move:
// coefficient +w on side A's, -w on side B's (summed where the two share a texel), and the
// part the fixed texels read (A - B; 0 when they hold 0, as unfilled texels do).
struct SeamPoint {
  uint32_t texel[8];
  float coefficient[8];
  uint32_t count = 0;
  float inverse_norm = 0;  // 1 / the sum of the squared coefficients
  glm::vec3 fixed{0.0f};
};

SeamPoint constraint(const RgbImage& image, const Side& a, const Side& b) {
  SeamPoint p;
  const auto add = [&](uint32_t texel, float c) {
    for (uint32_t i = 0; i < p.count; ++i) {
      if (p.texel[i] == texel) {
        p.coefficient[i] += c;
        return;
      }
    }
    p.texel[p.count] = texel;
    p.coefficient[p.count++] = c;
  };
  for (int i = 0; i < a.movable.count; ++i) add(a.movable.texel[i], a.movable.weight[i]);
  for (int i = 0; i < b.movable.count; ++i) add(b.movable.texel[i], -b.movable.weight[i]);
  float norm = 0;
  glm::vec3 movable(0.0f);
  for (uint32_t i = 0; i < p.count; ++i) {
    norm += p.coefficient[i] * p.coefficient[i];
    movable += p.coefficient[i] * image.pixels[p.texel[i]];
  }
  p.inverse_norm = norm > 1e-12f ? 1.0f / norm : 0.0f;
  p.fixed = read(image, a.all) - read(image, b.all) - movable;
  return p;
}

// A - B at the point, as the image reads it now.
glm::vec3 mismatch(const RgbImage& image, const SeamPoint& p) {
  glm::vec3 d = p.fixed;
  for (uint32_t i = 0; i < p.count; ++i) d += p.coefficient[i] * image.pixels[p.texel[i]];
  return d;
}

// Sweeps over one batch of points (see stitch_seams), adding to the report.
void solve(RgbImage& image, const std::vector<SeamPoint>& points, float scale,
           const SeamStitchOptions& options, SeamStitchReport& report) {
  float before = 0;
  for (const SeamPoint& p : points)
    before = std::max(before, largest_component(mismatch(image, p)));
  report.points += points.size();
  report.mismatch_before = std::max(report.mismatch_before, before);
  const float tolerance = options.relative_tolerance * scale;
  float after = before;
  if (before > tolerance) {
    for (uint32_t pass = 0; pass < options.max_passes; ++pass) {
      float largest = 0;  // the largest mismatch met in this sweep (before each step)
      for (const SeamPoint& p : points) {
        const glm::vec3 d = mismatch(image, p);
        largest = std::max(largest, largest_component(d));
        // The smallest change (least squares) that makes both sides read the same.
        const glm::vec3 step = d * p.inverse_norm;
        for (uint32_t i = 0; i < p.count; ++i) image.pixels[p.texel[i]] -= p.coefficient[i] * step;
      }
      report.passes = std::max(report.passes, pass + 1);
      if (largest <= tolerance) break;
    }
    after = 0;
    for (const SeamPoint& p : points)
      after = std::max(after, largest_component(mismatch(image, p)));
  }
  report.mismatch_after = std::max(report.mismatch_after, after);
}

}  // namespace

glm::vec3 bilinear_lookup(const RgbImage& image, glm::vec2 uv) {
  if (image.width == 0 || image.height == 0) return glm::vec3(0.0f);
  return read(image, footprint(image.width, image.height, uv));
}

SeamStitchReport stitch_seams(RgbImage& image, const std::vector<uint8_t>& covered,
                              const std::vector<uint8_t>& filled,
                              const std::vector<LightmapSeam>& seams,
                              const SeamStitchOptions& options) {
  SeamStitchReport report;
  if (filled.size() != image.pixels.size() || covered.size() != image.pixels.size() ||
      image.pixels.size() != size_t(image.width) * image.height) {
    throw Error(BAKEGI_ERROR_INTERNAL, "stitch_seams: mask and image sizes differ");
  }
  if (seams.empty() || image.pixels.empty()) return report;

  const glm::vec2 size(float(image.width), float(image.height));
  // A seam's points: both ends and every half texel of its longer side between them (at
  // least the two ends); at most 4 (W + H) + 1, twice the longest a segment clipped to the
  // map can be, so that UVs far outside the map (clipped by the rasterizer) cannot ask for
  // billions. The ends are where charts meet at a corner and where most of the mismatch
  // is left without them (on the Cornell atlas, the largest relative mismatch after 50
  // sweeps: 3.9% with them, 9.5% with midpoints only); an end shared by two seam edges is
  // constrained twice, by the same equation, which changes nothing.
  const double max_segments = 4.0 * (double(image.width) + image.height);
  // Points are solved in batches (SeamStitchOptions::batch_points; 84 bytes each), so that
  // a huge atlas of tiny charts stitches in bounded memory; seams of different batches
  // that share texels (at a chart's corner) are solved one batch after the other, and the
  // later one may leave a small mismatch in the earlier.
  const size_t batch_points = std::max<size_t>(options.batch_points, 1);
  std::vector<SeamPoint> points;
  points.reserve(std::min(batch_points, 64 * seams.size()));
  float scale = 0;  // the largest value read along the batch's seams
  for (const LightmapSeam& seam : seams) {
    const float length = std::max(glm::length((seam.a[1] - seam.a[0]) * size),
                                  glm::length((seam.b[1] - seam.b[0]) * size));
    const uint32_t segments =
        uint32_t(std::clamp(std::ceil(2.0 * double(length)), 1.0, max_segments));
    for (uint32_t k = 0; k <= segments; ++k) {
      const float s = float(k) / float(segments);
      const Side a = side(image, covered, filled, glm::mix(seam.a[0], seam.a[1], s));
      const Side b = side(image, covered, filled, glm::mix(seam.b[0], seam.b[1], s));
      if (!a.baked || !b.baked) continue;
      const SeamPoint p = constraint(image, a, b);
      if (p.inverse_norm == 0) continue;
      scale = std::max(scale, std::max(largest_component(read(image, a.all)),
                                       largest_component(read(image, b.all))));
      points.push_back(p);
      if (points.size() == batch_points) {
        solve(image, points, scale, options, report);
        points.clear();
        scale = 0;
      }
    }
  }
  if (!points.empty()) solve(image, points, scale, options, report);
  return report;
}

}  // namespace bakegi
