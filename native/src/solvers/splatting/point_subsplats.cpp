#include "solvers/splatting/point_subsplats.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/job_context.h"

namespace bakegi {

namespace {

constexpr uint32_t kNoSubsplat = 0xFFFFFFFFu;
constexpr float kNormalAgreement = 0.7071f;  // cos 45 degrees

struct Grid {
  glm::vec3 origin;
  float finest_size;
  uint32_t coarsest;
  float size(uint32_t level) const { return std::ldexp(finest_size, int(level)); }
  uint64_t key(const glm::vec3& p, uint32_t level) const {
    const glm::vec3 q = (p - origin) / size(level);
    const auto axis = [](float v) { return uint64_t(std::clamp(v, 0.0f, 2097151.0f)); };
    return axis(q.x) | axis(q.y) << 21 | axis(q.z) << 42;
  }
};

uint64_t neighbour(uint64_t key, int dx, int dy, int dz, bool& inside) {
  const int64_t x = int64_t(key & 0x1FFFFF) + dx, y = int64_t(key >> 21 & 0x1FFFFF) + dy,
                z = int64_t(key >> 42 & 0x1FFFFF) + dz;
  inside = x >= 0 && y >= 0 && z >= 0 && x < 2097152 && y < 2097152 && z < 2097152;
  return uint64_t(x) | uint64_t(y) << 21 | uint64_t(z) << 42;
}

struct Subsplat {
  uint32_t level;
  uint32_t representative;
};

bool discontinuous(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                   const std::vector<uint32_t>& ids, size_t begin, size_t end, float cell,
                   const PointSubsplatOptions& options) {
  if (end - begin < 2) return false;
  glm::vec3 lo(1e30f), hi(-1e30f), mean(0.0f), normal(0.0f);
  for (size_t i = begin; i < end; ++i) {
    const glm::vec3& n = normals[ids[i]];
    lo = glm::min(lo, n);
    hi = glm::max(hi, n);
    mean += positions[ids[i]];
    normal += n;
  }
  const glm::vec3 range = hi - lo;
  if (std::max(range.x, std::max(range.y, range.z)) > options.normal_threshold) return true;
  const float length = glm::length(normal);
  if (!(length > 0.5f * float(end - begin))) return true;
  normal /= length;
  mean /= float(end - begin);
  for (size_t i = begin; i < end; ++i) {
    if (std::abs(glm::dot(positions[ids[i]] - mean, normal)) > options.depth_threshold * cell) {
      return true;
    }
  }
  return false;
}

}  // namespace

void splat_at_points(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     const PointSubsplatOptions& options, const PointLightFunction& light,
                     std::span<glm::vec3> out, PointSubsplatStatistics& statistics,
                     JobContext& context) {
  const size_t n = positions.size();
  if (n == 0) return;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const float extent = std::max(std::max(hi.x - lo.x, hi.y - lo.y), std::max(hi.z - lo.z, 1e-6f));
  Grid grid;
  grid.origin = lo - glm::vec3(1e-4f * extent);
  const float coarsest_size = 1.0001f * extent / float(std::max(1u, options.base_resolution));
  // Finest cells about half the spacing of points spread over surfaces.
  const float spacing = extent / std::sqrt(float(n));
  grid.coarsest = uint32_t(std::clamp(
      std::ceil(std::log2(coarsest_size / std::max(0.5f * spacing, 1e-9f))), 0.0f, 16.0f));
  grid.finest_size = std::ldexp(coarsest_size, -int(grid.coarsest));
  statistics.per_level.assign(grid.coarsest + 1, 0);

  // Refinement (§3.3): ranges of `ids` sorted by cell, split level by level.
  std::vector<uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0u);
  std::vector<uint32_t> subsplat_of(n, kNoSubsplat);
  std::vector<Subsplat> subsplats;
  std::vector<uint32_t> single_points;
  struct Range {
    uint32_t level;
    size_t begin, end;
  };
  // Sorts ids[begin, end) by their cell at `level` (each key computed once) and appends one
  // range per cell.
  std::vector<std::pair<uint64_t, uint32_t>> keyed;
  const auto push_cells = [&](size_t begin, size_t end, uint32_t level,
                              std::vector<Range>& out_ranges) {
    keyed.clear();
    for (size_t i = begin; i < end; ++i)
      keyed.push_back({grid.key(positions[ids[i]], level), ids[i]});
    std::sort(keyed.begin(), keyed.end());
    for (size_t i = 0; i < keyed.size(); ++i) ids[begin + i] = keyed[i].second;
    for (size_t i = 0; i < keyed.size();) {
      size_t j = i + 1;
      while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
      out_ranges.push_back({level, begin + i, begin + j});
      i = j;
    }
  };
  std::vector<Range> work;
  push_cells(0, n, grid.coarsest, work);
  while (!work.empty()) {
    const Range r = work.back();
    work.pop_back();
    if (discontinuous(positions, normals, ids, r.begin, r.end, grid.size(r.level), options)) {
      if (r.level > 0) {
        push_cells(r.begin, r.end, r.level - 1, work);
      } else {
        for (size_t i = r.begin; i < r.end; ++i) single_points.push_back(ids[i]);
      }
      continue;
    }
    // One subsplat: its point nearest the centroid reads the light.
    glm::vec3 centroid(0.0f);
    for (size_t i = r.begin; i < r.end; ++i) centroid += positions[ids[i]];
    centroid /= float(r.end - r.begin);
    uint32_t best = ids[r.begin];
    float best_d = 1e30f;
    for (size_t i = r.begin; i < r.end; ++i) {
      const glm::vec3 d = positions[ids[i]] - centroid;
      if (glm::dot(d, d) < best_d) best_d = glm::dot(d, d), best = ids[i];
      subsplat_of[ids[i]] = uint32_t(subsplats.size());
    }
    subsplats.push_back({r.level, best});
    ++statistics.per_level[r.level];
  }
  statistics.single_points = single_points.size();
  context.throw_if_cancelled();

  // Rendering (§3.4): the light at each subsplat's point and at each single point.
  std::vector<glm::vec3> value(subsplats.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, subsplats.size(), 16), [&](const auto& r) {
    for (size_t s = r.begin(); s != r.end(); ++s) {
      if (context.is_cancelled()) return;
      const uint32_t p = subsplats[s].representative;
      value[s] = light(positions[p], normals[p], p);
    }
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, single_points.size(), 16), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (context.is_cancelled()) return;
      const uint32_t p = single_points[i];
      out[p] = light(positions[p], normals[p], p);
    }
  });
  statistics.evaluations = subsplats.size() + single_points.size();
  context.throw_if_cancelled();

  // Upsampling (§3.5), coarsest to finest, over the cells that hold light at each level.
  struct Cell {
    glm::vec3 light{0.0f};
    glm::vec3 normal{0.0f};
    glm::vec3 filtered{0.0f};
    bool rendered = false;
  };
  std::unordered_map<uint64_t, glm::vec3> parent_filtered;
  for (int k = int(grid.coarsest); k >= 0; --k) {
    const uint32_t level = uint32_t(k);
    std::unordered_map<uint64_t, Cell> cells;
    for (size_t p = 0; p < n; ++p) {
      const uint32_t s = subsplat_of[p];
      if (s == kNoSubsplat || subsplats[s].level < level) continue;
      Cell& c = cells[grid.key(positions[p], level)];
      c.normal += normals[p];
      if (subsplats[s].level == level) {
        c.light = value[s];
        c.rendered = true;
      } else if (!c.rendered) {
        c.light = parent_filtered.at(grid.key(positions[p], level + 1));
      }
    }
    std::vector<std::pair<const uint64_t, Cell>*> list;
    list.reserve(cells.size());
    for (auto& entry : cells) {
      entry.second.normal = glm::normalize(entry.second.normal + glm::vec3(1e-30f));
      list.push_back(&entry);
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, list.size(), 64), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        Cell& c = list[i]->second;
        glm::vec3 sum(0.0f);
        float total = 0.0f;
        for (int dz = -1; dz <= 1; ++dz) {
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              bool inside = false;
              const uint64_t key = neighbour(list[i]->first, dx, dy, dz, inside);
              if (!inside) continue;
              const auto it = cells.find(key);
              if (it == cells.end() || glm::dot(it->second.normal, c.normal) < kNormalAgreement) {
                continue;
              }
              const float w = float((2 - std::abs(dx)) * (2 - std::abs(dy)) * (2 - std::abs(dz)));
              sum += w * it->second.light;
              total += w;
            }
          }
        }
        c.filtered = total > 0.0f ? sum / total : c.light;
      }
    });
    parent_filtered.clear();
    for (auto& entry : cells) parent_filtered[entry.first] = entry.second.filtered;
    context.throw_if_cancelled();
  }
  for (size_t p = 0; p < n; ++p) {
    if (subsplat_of[p] != kNoSubsplat) out[p] = parent_filtered.at(grid.key(positions[p], 0));
  }
}

}  // namespace bakegi
