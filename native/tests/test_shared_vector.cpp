// The scene description's copy-on-write meshes: copies share one storage until one of them
// changes, a change never reaches another copy, and equal contents compare equal without
// shared storage.
#include <gtest/gtest.h>

#include "scene/scene.h"

namespace bakegi {
namespace {

Mesh triangle(float x) {
  Mesh mesh;
  mesh.positions = {{x, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  return mesh;
}

TEST(SharedVector, CopiesShareUntilOneChanges) {
  SceneDescription original;
  original.meshes.push_back(triangle(0.0f));
  const SceneDescription copy = original;  // as a job copies the caller's scene
  EXPECT_TRUE(copy.meshes.shares_storage_with(original.meshes));
  EXPECT_EQ(&copy.meshes[0], &std::as_const(original.meshes)[0]);

  SceneDescription changed = copy;
  changed.meshes[0].positions[0].x = 5.0f;  // detaches `changed` only
  EXPECT_FALSE(changed.meshes.shares_storage_with(copy.meshes));
  EXPECT_EQ(copy.meshes[0].positions[0].x, 0.0f);
  EXPECT_EQ(std::as_const(original.meshes)[0].positions[0].x, 0.0f);
  EXPECT_NE(changed.meshes, copy.meshes);

  original.meshes.push_back(triangle(2.0f));  // the original's own change leaves the copy
  EXPECT_EQ(copy.meshes.size(), 1u);
  EXPECT_EQ(original.meshes.size(), 2u);
}

TEST(SharedVector, EqualContentsAreEqualWithoutSharing) {
  SceneDescription a, b;
  a.meshes.push_back(triangle(0.0f));
  b.meshes.push_back(triangle(0.0f));
  EXPECT_FALSE(a.meshes.shares_storage_with(b.meshes));
  EXPECT_EQ(a.meshes, b.meshes);
  b.meshes.push_back(triangle(1.0f));
  EXPECT_NE(a.meshes, b.meshes);
}

}  // namespace
}  // namespace bakegi
