// The core's Light as the C API describes it (bakegi_light_desc): what
// bakegi_scene_get_light returns, and what code that rebuilds a scene through the C API
// (the benchmarks) passes to bakegi_scene_add_light.
#pragma once

#include "bakegi/bakegi.h"
#include "scene/scene.h"

namespace bakegi {

inline bakegi_light_desc to_light_desc(const Light& l) {
  auto put = [](const glm::vec3& v, float* out) {
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
  };
  bakegi_light_desc d{};
  d.type = l.type;
  put(l.position, d.position);
  put(l.direction, d.direction);
  put(l.axis_u, d.axis_u);
  put(l.color, d.color);
  d.radius = l.radius;
  d.spot_size = l.spot_size;
  d.spot_blend = l.spot_blend;
  d.angle = l.angle;
  d.shape = l.shape;
  d.size_x = l.size_x;
  d.size_y = l.size_y;
  d.flags = l.flags;
  return d;
}

}  // namespace bakegi
