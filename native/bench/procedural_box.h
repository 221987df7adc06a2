// A Cornell box built in code (same room, boxes, colours and light as scenes/cornell_box.py,
// walls as grids of quads), so that the benchmarks run without Blender or a scene file.
#pragma once

#include "scene/bake_points.h"
#include "scene/scene.h"

namespace bakegi::bench {

// `cells` grid cells along a 2 m wall edge (the Blender scene's default is 32).
SceneDescription procedural_box(int cells = 32);
// One bake point per triangle of the flattened scene, at its centroid with its normal.
BakePoints triangle_centroid_points(const Scene& scene);

}  // namespace bakegi::bench
