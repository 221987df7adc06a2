// Where the indirect field is evaluated: vertices, face corners or lightmap texels, all
// reduced to (position, shading normal, object). Solvers never know which.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct BakePoints {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // unit length (normalized on input)
  std::vector<uint32_t> object_ids;
  // Empty, or per point an earlier point (or itself) that the exporter says lies at the same
  // place with the same normal, whose value it may share (bake/point_sharing.h checks).
  std::vector<uint32_t> share_candidates;
  size_t size() const { return positions.size(); }
};

}  // namespace bakegi
