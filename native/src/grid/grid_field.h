// A grid behind the IndirectField interface (issue 16, item 2), so that a grid lights bake
// points, lightmap texels and meshes that were not in the bake alike: each point read as
// grid/grid_visibility.h reads it (with both of its tests off: the paper's reading), in
// chunks between progress reports and cancel. The report counts the unsure and buried points
// and warns about the unsure ones.
#pragma once

#include "field/indirect_field.h"
#include "grid/grid_visibility.h"
#include "grid/irradiance_vector_grid.h"

namespace bakegi {

class RayTracer;
struct Scene;

class GridField : public IndirectField {
 public:
  // The scene and ray tracer are the job's (they outlive the field, indirect_field.h).
  GridField(IrradianceVectorGrid grid, const GridSceneLookup& lookup, const Scene& scene,
            const RayTracer& tracer)
      : grid_(std::move(grid)), lookup_(lookup), scene_(scene), tracer_(tracer) {}

  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override;

 private:
  IrradianceVectorGrid grid_;
  GridSceneLookup lookup_;
  const Scene& scene_;
  const RayTracer& tracer_;
};

}  // namespace bakegi
