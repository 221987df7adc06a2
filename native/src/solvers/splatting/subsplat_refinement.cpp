#include "solvers/splatting/subsplat_refinement.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "solvers/splatting/virtual_point_lights.h"
#include "util/luminance.h"

namespace bakegi {

namespace {

std::vector<Subsplat> coarsest_subsplats(const MinMaxMipmap& mipmap, uint32_t coarsest) {
  std::vector<Subsplat> out;
  const MipLevel& l = mipmap.level(coarsest);
  for (uint32_t y = 0; y < l.height; ++y) {
    for (uint32_t x = 0; x < l.width; ++x) {
      if (l.hits[l.index(x, y)] > 0) out.push_back({coarsest, x, y});
    }
  }
  return out;
}

// The children of s that see a surface, in the paper's order (top left, top right, bottom
// right, bottom left).
template <typename Visit>
void for_each_child(const MinMaxMipmap& mipmap, const Subsplat& s, Visit&& visit) {
  const MipLevel& fine = mipmap.level(s.level - 1);
  const uint32_t offsets[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& o : offsets) {
    const uint32_t x = 2 * s.x + o[0], y = 2 * s.y + o[1];
    if (x < fine.width && y < fine.height && fine.hits[fine.index(x, y)] > 0) {
      visit(Subsplat{s.level - 1, x, y});
    }
  }
}

SubsplatSet counted(std::vector<Subsplat> subsplats, uint32_t levels) {
  SubsplatSet set;
  set.per_level.assign(levels, 0);
  for (const Subsplat& s : subsplats) ++set.per_level[s.level];
  set.subsplats = std::move(subsplats);
  return set;
}

glm::vec3 light_at(const MinMaxMipmap& mipmap, const EyeGBuffer& g, const VirtualPointLights& vpls,
                   size_t vpl, const Subsplat& s) {
  const uint32_t pixel =
      mipmap.level(s.level).representative[mipmap.level(s.level).index(s.x, s.y)];
  return vpl_term_over_pi(vpls, vpl, g.position[pixel], g.normal[pixel]);
}

}  // namespace

SubsplatSet refine_subsplats(const MinMaxMipmap& mipmap, uint32_t coarsest, uint32_t finest,
                             const DiscontinuityTest& test) {
  std::vector<Subsplat> current = coarsest_subsplats(mipmap, coarsest);
  std::vector<Subsplat> done;
  for (uint32_t k = coarsest; k > finest; --k) {
    std::vector<Subsplat> next;
    for (const Subsplat& s : current) {
      if (mipmap.refines(k, s.x, s.y, test)) {
        for_each_child(mipmap, s, [&](const Subsplat& c) { next.push_back(c); });
      } else {
        done.push_back(s);
      }
    }
    current = std::move(next);
  }
  done.insert(done.end(), current.begin(), current.end());
  return counted(std::move(done), mipmap.levels());
}

SubsplatSet refine_subsplats_by_light(const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer,
                                      uint32_t coarsest, uint32_t finest,
                                      const DiscontinuityTest& test, float threshold,
                                      const SurfaceLight& light, std::vector<glm::vec3>& values) {
  std::vector<Subsplat> current = coarsest_subsplats(mipmap, coarsest);
  std::vector<Subsplat> done;
  values.clear();
  // Which texel of a level holds which kept subsplat (-1: none), sized once for the finest
  // level and reused by the coarser ones.
  std::vector<int32_t> at;
  // Per subsplat of a pass: whether it splits (bytes, so that threads write their own).
  std::vector<uint8_t> splits;
  const auto in_parallel = [](size_t n, auto&& body) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) body(i);
    });
  };
  for (uint32_t k = coarsest;; --k) {
    // The geometry's splits first: their subsplats never read light at this level.
    splits.assign(current.size(), 0);
    if (k > finest) {
      in_parallel(current.size(), [&](size_t i) {
        splits[i] = mipmap.refines(k, current[i].x, current[i].y, test) ? 1 : 0;
      });
    }
    std::vector<Subsplat> next, kept;
    for (size_t i = 0; i < current.size(); ++i) {
      if (splits[i]) {
        for_each_child(mipmap, current[i], [&](const Subsplat& c) { next.push_back(c); });
      } else {
        kept.push_back(current[i]);
      }
    }
    const MipLevel& l = mipmap.level(k);
    std::vector<glm::vec3> light_of(kept.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, kept.size(), 32), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        light_of[i] = light(mipmap.point(gbuffer, k, kept[i].x, kept[i].y, test));
      }
    });
    splits.assign(kept.size(), 0);
    if (k > finest && threshold > 0.0f) {
      at.assign(size_t(l.width) * l.height, -1);
      for (size_t i = 0; i < kept.size(); ++i) at[l.index(kept[i].x, kept[i].y)] = int32_t(i);
      const auto y_of = [&](int32_t i) { return float(luminance(light_of[size_t(i)])); };
      const auto neighbour = [&](const Subsplat& s, int dx, int dy) {
        const int x = int(s.x) + dx, y = int(s.y) + dy;
        if (x < 0 || y < 0 || x >= int(l.width) || y >= int(l.height)) return int32_t(-1);
        return at[l.index(uint32_t(x), uint32_t(y))];
      };
      in_parallel(kept.size(), [&](size_t i) {
        const float v = y_of(int32_t(i));
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
          const int32_t a = neighbour(kept[i], -dx, -dy);
          const int32_t b = neighbour(kept[i], dx, dy);
          float second = 0.0f;
          if (a >= 0 && b >= 0) {
            second = y_of(a) + y_of(b) - 2.0f * v;
          } else if (a >= 0 || b >= 0) {
            // Beside a region refined further (an edge, where light often peaks): the
            // one-sided second difference over the next two texels away from it.
            const int side = a >= 0 ? -1 : 1;
            const int32_t far = neighbour(kept[i], 2 * side * dx, 2 * side * dy);
            if (far < 0) continue;
            second = v + y_of(far) - 2.0f * y_of(a >= 0 ? a : b);
          }
          if (std::abs(second) > threshold * v) splits[i] = 1;
        }
      });
    }
    for (size_t i = 0; i < kept.size(); ++i) {
      if (splits[i]) {
        for_each_child(mipmap, kept[i], [&](const Subsplat& c) { next.push_back(c); });
      } else {
        done.push_back(kept[i]);
        values.push_back(light_of[i]);
      }
    }
    current = std::move(next);
    if (current.empty() || k == 0) break;
  }
  return counted(std::move(done), mipmap.levels());
}

uint64_t illumination_refined_subsplats(
    const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer, const VirtualPointLights& vpls,
    size_t vpl, uint32_t coarsest, uint32_t finest, float threshold, float floor,
    const std::function<void(const Subsplat&, const glm::vec3&)>& emit) {
  std::vector<Subsplat> stack = coarsest_subsplats(mipmap, coarsest);
  uint64_t emitted = 0;
  while (!stack.empty()) {
    const Subsplat s = stack.back();
    stack.pop_back();
    if (s.level > finest) {
      // SamplesDiffer: component-wise range of the quadrants' light against the threshold.
      glm::vec3 lo(1e30f), hi(0.0f), sum(0.0f);
      Subsplat children[4];
      int count = 0;
      for_each_child(mipmap, s, [&](const Subsplat& c) {
        const glm::vec3 v = light_at(mipmap, gbuffer, vpls, vpl, c);
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
        sum += v;
        children[count++] = c;
      });
      const glm::vec3 range = hi - lo;
      const float mean = std::max(std::max(sum.x, std::max(sum.y, sum.z)) / float(count), floor);
      if (count > 0 && std::max(range.x, std::max(range.y, range.z)) > threshold * mean) {
        for (int c = 0; c < count; ++c) stack.push_back(children[c]);
        continue;
      }
    }
    emit(s, light_at(mipmap, gbuffer, vpls, vpl, s));
    ++emitted;
  }
  return emitted;
}

}  // namespace bakegi
