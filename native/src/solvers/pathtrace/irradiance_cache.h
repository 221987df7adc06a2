// An irradiance cache (issue 15, item 6; Ward, Rubinstein and Clear 1988, with the gradients
// of Ward and Heckbert 1992): where bake points lie closer together than the indirect light
// changes, gather at a sparse set of them (the records) and interpolate the rest.
//
// A record i at x_i with normal n_i holds E_i/π, its gradients (irradiance_gradients.h) and
// a radius R_i: the harmonic mean distance to what its gather hit, at most 10% of the bake
// points' extent and at most E_i / |∇_t E_i| (where the light changes fast, records are
// closer). A point (x, n) may use record i where
//     ε_i = |x − x_i| / min(R_i, R_x) + sqrt(1 − n · n_i)  <  a,
// a the cache's accuracy (Ward's error bound: the relative change of irradiance the paper
// allows across a record, about ε), R_x the point's own radius (measured the same way, where
// it is known: a point in a crevice must not take light from a record in the open; Ward
// bounds only by R_i), and x does not lie behind record i's surface. The value
// at x is the weighted mean of the records' first-order predictions
//     E_i + (n_i × n) · ∇_r E_i + (x − x_i) · ∇_t E_i,   weight 1/ε_i − 1/a,
// whose weights fall to 0 at the edge of each record's reach, so the result is continuous.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/pathtrace/irradiance_gradients.h"

namespace bakegi {

struct IrradianceRecord {
  glm::vec3 position{0.0f}, normal{0.0f, 0.0f, 1.0f};
  IrradianceGather gather;
  float radius = 0.0f;  // R_i
};

// R_i of a gather: its harmonic mean distance, at most max_radius and E / |∇_t E|
// (luminance).
float record_radius(const IrradianceGather& gather, float max_radius);

// Records near a point, whatever their reach: a hash grid per power-of-two cell size, each
// record in the one cell of the level whose cells are at least its reach wide; a query
// looks at the 27 cells around the point on every level in use.
class RecordIndex {
 public:
  // `smallest_cell`: the level-0 cell (reaches below it share level 0).
  explicit RecordIndex(float smallest_cell) : smallest_cell_(smallest_cell) {}
  void insert(uint32_t record, const glm::vec3& centre, float reach);
  // Calls visit(record) for every record inserted with a reach it might have to x (and
  // others).
  template <typename Visit>
  void for_each_near(const glm::vec3& x, Visit&& visit) const;

 private:
  struct Key {
    int32_t level, x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const;
  };
  Key key_of(int level, const glm::vec3& p) const;
  float smallest_cell_;
  uint32_t levels_in_use_ = 0;  // bit per level
  std::unordered_map<Key, std::vector<uint32_t>, KeyHash> cells_;
};

// The records and their interpolation.
class IrradianceCache {
 public:
  IrradianceCache(float accuracy, float smallest_radius)
      : accuracy_(accuracy), index_(accuracy * smallest_radius) {}

  uint32_t add(const IrradianceRecord& record);
  const std::vector<IrradianceRecord>& records() const { return records_; }
  float accuracy() const { return accuracy_; }

  // Whether some record may be used at (x, n) (skipping record `except`). `own_radius`: the
  // point's own radius (its pilot's harmonic mean distance); the distance term uses the
  // smaller of the two radii, so a point whose surroundings are close (a vertex in a crevice,
  // under a ledge, inside other geometry) does not take light from a record out in the open.
  bool covers(const glm::vec3& x, const glm::vec3& n, float own_radius = kNoRadius,
              uint32_t except = UINT32_MAX) const;

  struct Interpolated {
    glm::vec3 value{0.0f};
    float luminance_variance_of_mean = 0.0f;  // of the records' noise the weights carry
    bool covered = false;
  };
  Interpolated interpolate(const glm::vec3& x, const glm::vec3& n, float own_radius = kNoRadius,
                           uint32_t except = UINT32_MAX) const;
  static constexpr float kNoRadius = 3.0e38f;

 private:
  // ε_i of record i at (x, n), or a value >= a where record i may not be used.
  float error_of(const IrradianceRecord& record, const glm::vec3& x, const glm::vec3& n,
                 float own_radius) const;
  float accuracy_;
  std::vector<IrradianceRecord> records_;
  RecordIndex index_;
};

template <typename Visit>
void RecordIndex::for_each_near(const glm::vec3& x, Visit&& visit) const {
  for (int level = 0; level < 32; ++level) {
    if (!(levels_in_use_ & (1u << level))) continue;
    const Key centre = key_of(level, x);
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const auto found = cells_.find(Key{level, centre.x + dx, centre.y + dy, centre.z + dz});
          if (found == cells_.end()) continue;
          for (const uint32_t record : found->second) visit(record);
        }
      }
    }
  }
}

}  // namespace bakegi
