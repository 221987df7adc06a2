// Completing the coarse levels a query cannot see through the finer points it sees
// (level_completion.h): the rule on hand-made relations, and the identity that makes it
// consistent with the projection (a finest point completed through itself gets back its own
// sample, whatever its coarser levels hide).
#include <gtest/gtest.h>

#include <vector>

#include "meshless_test_scenes.h"
#include "scene/ray_tracer.h"
#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/level_completion.h"
#include "solvers/meshless/visible_basis.h"
#include "util/random.h"

namespace bakegi {
namespace {

using meshless::BasisHierarchy;
using meshless::BasisPoint;
using meshless::BasisValue;
using test::floor_point;

// Three levels on a floor: 0 = {0, 1}, 1 = {2, 3}, 2 = {4, 5}.
BasisHierarchy three_levels() {
  return BasisHierarchy({floor_point(-1.0f, 4.0f, 0), floor_point(1.0f, 4.0f, 0),
                         floor_point(-0.5f, 2.0f, 1), floor_point(0.5f, 2.0f, 1),
                         floor_point(-0.25f, 1.0f, 2), floor_point(0.25f, 1.0f, 2)});
}

// Coarser relations written by hand (the weights need not be a basis' own: the rule only
// reads them).
meshless::VisibleRelations hand_relations() {
  meshless::VisibleRelations r;
  // 0, 1: none; 2: (0, 1); 3: (1, 1); 4: (0, 0.25) (1, 0.75) (2, 1); 5: (3, 1) only (blind
  // to level 0).
  r.coarser = {{0, 1.0f}, {1, 1.0f}, {0, 0.25f}, {1, 0.75f}, {2, 1.0f}, {3, 1.0f}};
  r.coarser_offsets = {0, 0, 0, 1, 2, 5, 6};
  return r;
}

float weight_of(const std::vector<BasisValue>& row, uint32_t index, size_t from) {
  float sum = 0.0f;
  for (size_t e = from; e < row.size(); ++e) {
    if (row[e].index == index) sum += row[e].value;
  }
  return sum;
}

TEST(MeshlessLevelCompletion, AMissingLevelTurnsTheRowIntoTheFinestLevelSeenAndItsRelations) {
  const BasisHierarchy basis = three_levels();
  const meshless::VisibleRelations relations = hand_relations();

  // Sees only level 2 (4: 0.6, 5: 0.4): levels 0 and 1 come through 4 and 5.
  std::vector<BasisValue> row = {{4, 0.6f}, {5, 0.4f}};
  EXPECT_EQ(meshless::complete_missing_levels(basis, relations, row), 2u);
  EXPECT_FLOAT_EQ(weight_of(row, 4, 0), 0.6f);
  EXPECT_FLOAT_EQ(weight_of(row, 5, 0), 0.4f);
  EXPECT_FLOAT_EQ(weight_of(row, 0, 0), 0.6f * 0.25f);
  EXPECT_FLOAT_EQ(weight_of(row, 1, 0), 0.6f * 0.75f);
  EXPECT_FLOAT_EQ(weight_of(row, 2, 0), 0.6f * 1.0f);
  EXPECT_FLOAT_EQ(weight_of(row, 3, 0), 0.4f * 1.0f);

  // Sees levels 1 and 2 but not 0: the query's own level-1 weights give way to those of the
  // level-2 point's relations (what its coefficient is the difference from).
  row = {{3, 1.0f}, {4, 1.0f}};
  EXPECT_EQ(meshless::complete_missing_levels(basis, relations, row), 1u);
  EXPECT_FLOAT_EQ(weight_of(row, 3, 0), 0.0f);
  EXPECT_FLOAT_EQ(weight_of(row, 2, 0), 1.0f);
  EXPECT_FLOAT_EQ(weight_of(row, 0, 0), 0.25f);
  EXPECT_FLOAT_EQ(weight_of(row, 1, 0), 0.75f);
  EXPECT_FLOAT_EQ(weight_of(row, 4, 0), 1.0f);

  // Nothing missing below the finest level seen: the row stays as it is.
  for (std::vector<BasisValue> full : {std::vector<BasisValue>{{1, 1.0f}},
                                       std::vector<BasisValue>{{0, 0.5f}, {1, 0.5f}, {3, 1.0f}}}) {
    row = full;
    EXPECT_EQ(meshless::complete_missing_levels(basis, relations, row), 0u);
    ASSERT_EQ(row.size(), full.size());
    for (size_t e = 0; e < row.size(); ++e) EXPECT_EQ(row[e].index, full[e].index);
  }

  // Sees nothing: nothing to complete from.
  row.clear();
  EXPECT_EQ(meshless::complete_missing_levels(basis, relations, row), 0u);
  EXPECT_TRUE(row.empty());

  // A finer point that is itself blind to a level adds nothing there: its coefficient holds
  // that level's share already.
  row = {{5, 1.0f}};
  EXPECT_EQ(meshless::complete_missing_levels(basis, relations, row), 2u);
  EXPECT_FLOAT_EQ(weight_of(row, 3, 0), 1.0f);
  EXPECT_FLOAT_EQ(weight_of(row, 0, 0) + weight_of(row, 1, 0), 0.0f);
}

// With the relations a wall makes (some fine points blind to coarse ones), a finest point
// queried through itself alone gets back exactly its sample: the completed coarse levels
// carry what its coefficient was made the difference from (Eq. 7), no more.
TEST(MeshlessLevelCompletion, AFinestPointCompletedThroughItselfGetsBackItsSample) {
  const Scene scene = test::floor_with_wall();
  const RayTracer tracer(scene);
  std::vector<BasisPoint> points;
  Pcg32 rng(17, 3);
  const float radii[] = {2.5f, 1.2f, 0.6f};
  const int counts[] = {3, 8, 24};
  for (uint32_t level = 0; level < 3; ++level) {
    for (int i = 0; i < counts[level]; ++i) {
      BasisPoint p = floor_point(-1.4f + 2.8f * rng.next_float(), radii[level], level);
      p.position.y = -1.4f + 2.8f * rng.next_float();
      points.push_back(p);
    }
  }
  const BasisHierarchy basis(points);
  const meshless::VisibleRelations relations = meshless::visible_relations(basis, &tracer);
  ASSERT_GT(relations.blocked, 0u);  // the wall hides some coarse points from fine ones
  std::vector<float> samples(basis.size());
  for (float& s : samples) s = 0.5f + rng.next_float();
  const std::vector<float> alpha =
      meshless::visible_pull_push_project(basis, relations, samples, 1);

  size_t blind = 0;
  for (uint32_t j = basis.level_begin(2); j < basis.level_end(2); ++j) {
    std::vector<BasisValue> row = {{j, 1.0f}};
    meshless::complete_missing_levels(basis, relations, row);
    double value = 0.0;
    for (const BasisValue& b : row) value += double(b.value) * alpha[b.index];
    EXPECT_NEAR(value, samples[j], 1e-5) << "point " << j;
    // Points blind to a whole coarser level (the wall between): their α_j holds that
    // level's share too, and the completion must not add it a second time.
    bool sees_level[2] = {false, false};
    for (const BasisValue& c : relations.coarser_of(j)) sees_level[basis.point(c.index).level] = true;
    if (!sees_level[0] || !sees_level[1]) ++blind;
  }
  EXPECT_GT(blind, 0u);
}

}  // namespace
}  // namespace bakegi
