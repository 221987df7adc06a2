// Multiresolution splatting over bake points (issue 17, item 6): the paper's subsplats and
// upsampling (Nichols & Wyman 2009, §3.2-3.5) with cubic cells of a 3D grid in place of
// screen texels. The coarsest cells are 1/base_resolution of the points' extent; a cell
// splits into its eight children where its points hold a normal discontinuity (a component
// of their normals ranges over more than normal_threshold) or a position one (they stray
// from their mean plane by more than depth_threshold times the cell's size). A cell that
// stays whole is one subsplat: the light is evaluated once, at its point nearest the
// cell's centroid. A cell still discontinuous at the finest level evaluates each point.
//
// Upsampling is §3.5's: coarsest to finest, every cell holding light (its own, or brought
// down from its parent) is averaged with the 26 neighbours of its level that hold light
// (tent weights 1-2-1 per axis), among those whose mean normal agrees with its own (within
// 45 degrees: the 3D grid, unlike the screen, puts both sides of a thin wall side by side).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

class JobContext;

struct PointSubsplatOptions {
  uint32_t base_resolution = 16;
  float normal_threshold = 0.5f;
  float depth_threshold = 0.1f;
};

struct PointSubsplatStatistics {
  std::vector<uint64_t> per_level;  // subsplats whose light was evaluated, per level
  uint64_t single_points = 0;       // points still discontinuous at the finest level
  uint64_t evaluations = 0;
};

// Light at (position, shading normal, index of the point): thread-safe.
using PointLightFunction =
    std::function<glm::vec3(const glm::vec3& position, const glm::vec3& normal, size_t point)>;

void splat_at_points(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     const PointSubsplatOptions& options, const PointLightFunction& light,
                     std::span<glm::vec3> out, PointSubsplatStatistics& statistics,
                     JobContext& context);

}  // namespace bakegi
