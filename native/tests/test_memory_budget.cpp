// The bake's one memory budget: what is held counts against it, what remains never wraps
// below zero, and a solver called outside a job gets memory_budget_mb less its ray tracer.
#include <gtest/gtest.h>

#include "light_transport_fixtures.h"
#include "scene/scene_validation.h"
#include "solvers/solver.h"
#include "util/memory_budget.h"

namespace bakegi::test {
namespace {

TEST(MemoryBudget, HeldBytesLeaveTheRestAndNeverWrap) {
  MemoryBudget budget(1000);
  EXPECT_EQ(budget.remaining(), 1000u);
  budget.hold(300);
  EXPECT_EQ(budget.held(), 300u);
  EXPECT_EQ(budget.remaining(), 700u);
  EXPECT_EQ(budget.remaining_after(200), 500u);
  EXPECT_EQ(budget.remaining_after(700), 0u);
  EXPECT_EQ(budget.remaining_after(5000), 0u);
  budget.hold(2000);
  EXPECT_EQ(budget.remaining(), 0u);
  EXPECT_EQ(MemoryBudget(uint64_t(3) << 20).describe(), "3.0 MB (setting memory_budget_mb)");
  EXPECT_EQ(MemoryBudget().total(), uint64_t(4096) << 20);
}

TEST(MemoryBudget, OutsideAJobTheSettingLessTheRayTracer) {
  SceneDescription d;
  d.meshes.push_back(make_icosphere(glm::vec3(0.0f), 1.0f, 2, add_material(d, glm::vec3(0.5f))));
  d.lights.push_back(point_light(glm::vec3(0.0f), glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  Settings settings;
  settings.set("memory_budget_mb", int64_t(64));
  const MemoryBudget budget = memory_budget_for(settings, tracer);
  EXPECT_EQ(budget.total(), uint64_t(64) << 20);
  EXPECT_EQ(budget.held(), tracer.memory_bytes());
  EXPECT_GT(tracer.memory_bytes(), 0u);
  EXPECT_EQ(memory_budget_for(Settings(), tracer).total(), MemoryBudget::kDefaultBytes);
}

}  // namespace
}  // namespace bakegi::test
