// Reading light from the Irradiance Vector Grid at any (position, normal) (Pacanowski et al.
// 2008, §3.2). Spatial first: for each axis, the hemisphere on the normal's side of it (+x
// when n_x >= 0, ...) is interpolated at the position, trilinearly or with the tricubic
// B-spline of Sigg and Hadwiger 2005 (64 vertices, smoother, slower); then directional:
//   I_n = I_x n_x^2 + I_y n_y^2 + I_z n_z^2,
// exact when n lies along an axis (kSquared). Its weights sum to 1 but dotting the blend with
// n loses light for normals between the axes: under uniform light a normal at 45 degrees
// between two axes reads 1/sqrt(2) of the truth, one along a diagonal 1/sqrt(3).
// kAbsolute weighs by |n_a| instead: exact along the axes and under uniform light (the sum
// of n_a^2 is 1), too bright (up to sqrt(3)) for light concentrated in the normal's octant;
// measured against references in docs/ivg.md. The baked value (output convention E_indirect / pi)
// of channel c is max(0, I_n^c . n) / pi. Positions outside the grid take the nearest vertices'
// values (clamped). grid/grid_field.h puts a grid behind the IndirectField interface.
#pragma once

#include <functional>
#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "grid/irradiance_vector_grid.h"

namespace bakegi {

enum class GridInterpolation { kTrilinear = 0, kTricubic = 1 };
// The values of bakegi_grid_directional (bakegi.h).
enum class GridDirectionalWeights { kSquared = 0, kAbsolute = 1 };

// Which grid vertices a point may read (grid_visibility.h: those it sees), given the vertex's
// index and position.
using VertexFilter = std::function<bool(size_t vertex, const glm::vec3& position)>;

// With a filter, refused vertices drop out of the spatial interpolation and the others share
// their weight; if it refuses all, the point reads them all and *all_refused is set.
glm::vec3 evaluate_grid(const IrradianceVectorGrid& grid, const glm::vec3& position,
                        const glm::vec3& normal, GridInterpolation interpolation,
                        GridDirectionalWeights weights = GridDirectionalWeights::kSquared,
                        const VertexFilter* filter = nullptr, bool* all_refused = nullptr);

// evaluate_grid at every (positions[i], normals[i]) in parallel; normals need not be unit
// (a zero normal gives 0).
// The directional step alone: the value at a point of unit normal n from the given vertices
// with spatial weights that sum to 1.
glm::vec3 blend_vertices(const IrradianceVectorGrid& grid, const glm::vec3& n,
                         std::span<const size_t> vertices, std::span<const float> spatial,
                         GridDirectionalWeights weights);

void evaluate_grid(const IrradianceVectorGrid& grid, std::span<const glm::vec3> positions,
                   std::span<const glm::vec3> normals, std::span<glm::vec3> out,
                   GridInterpolation interpolation,
                   GridDirectionalWeights weights = GridDirectionalWeights::kSquared);

}  // namespace bakegi
