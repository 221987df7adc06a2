// A point on a surface as light transport sees it: where light is gathered and from which
// side. Made for bake points (position and normal given) and for ray hits.
#pragma once

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"
#include "scene/scene.h"

namespace bakegi {

// Both normals are unit and on the side light arrives from.
struct SurfacePoint {
  glm::vec3 position;
  glm::vec3 shading_normal;    // the diffuse lobe's normal
  glm::vec3 geometric_normal;  // the surface's side; rays leave from position + eps * this
};

// The surface a ray hit, seen from the ray's side (surfaces are two-sided): geometric normal
// facing back along the ray, interpolated shading normal turned to that side.
SurfacePoint surface_at_hit(const Scene& scene, const Hit& hit, const glm::vec3& ray_direction);

}  // namespace bakegi
