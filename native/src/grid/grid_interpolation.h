// Reading light from the Irradiance Vector Grid at any (position, normal) (Pacanowski et al.
// 2008, §3.2). Spatial first: for each axis, the hemisphere on the normal's side of it (+x
// when n_x >= 0, ...) is interpolated at the position, trilinearly or with the tricubic
// B-spline of Sigg and Hadwiger 2005 (64 vertices, smoother, slower); then directional:
//   I_n = I_x n_x^2 + I_y n_y^2 + I_z n_z^2,
// exact when n lies along an axis. The baked value (output convention E_indirect / pi) of
// channel c is max(0, I_n^c . n) / pi. Positions outside the grid take the nearest
// vertices' values (clamped).
//
// GridField puts a grid behind the IndirectField interface, so a grid lights bake points,
// lightmap texels and meshes that were not in the bake alike.
#pragma once

#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "field/indirect_field.h"
#include "grid/irradiance_vector_grid.h"

namespace bakegi {

enum class GridInterpolation { kTrilinear = 0, kTricubic = 1 };

glm::vec3 evaluate_grid(const IrradianceVectorGrid& grid, const glm::vec3& position,
                        const glm::vec3& normal, GridInterpolation interpolation);

// evaluate_grid at every (positions[i], normals[i]) in parallel; normals need not be unit
// (a zero normal gives 0).
void evaluate_grid(const IrradianceVectorGrid& grid, std::span<const glm::vec3> positions,
                   std::span<const glm::vec3> normals, std::span<glm::vec3> out,
                   GridInterpolation interpolation);

class GridField : public IndirectField {
 public:
  GridField(std::shared_ptr<const IrradianceVectorGrid> grid, GridInterpolation interpolation)
      : grid_(std::move(grid)), interpolation_(interpolation) {}
  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override;

 private:
  std::shared_ptr<const IrradianceVectorGrid> grid_;
  GridInterpolation interpolation_;
};

}  // namespace bakegi
