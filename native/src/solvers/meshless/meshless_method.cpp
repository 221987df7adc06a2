// The meshless method: its registration and its settings. Lighting: used again when lighting
// (§3.3), so a relight may change them and the precomputation cache ignores them; the rest
// shapes the precomputation and is part of its cache key. "visibility" shapes: the gather's
// visibility test (gather_integral.h) shapes T, so a relight or a cache hit with another value
// would reuse links made under the other rule.
#include "bake/precomputation_store.h"
#include "solvers/meshless/meshless_solver.h"
#include "solvers/method_registry.h"

namespace bakegi {

const std::vector<SettingSpec>& MeshlessSolver::setting_specs() {
  using R = SettingRole;
  static const std::vector<SettingSpec> specs = {
      integer_setting("levels", 0, 0, 12, R::kShapes,
                      "receiver levels of the basis; 0 = automatic (4)"),
      number_setting("coarse_spacing", 0.0, 0.0, 1e9, R::kShapes,
                     "Poisson-disk spacing of level 0 in metres; 0 = automatic"),
      integer_setting("sender_levels", 0, 0, 12, R::kShapes,
                      "levels that send light; 0 = all receiver levels but the finest"),
      number_setting("epsilon", 0.01, 0.0, 10.0, R::kShapes,
                     "link threshold in the paper's units (the paper used 0.025)"),
      integer_setting("gather_rays", 256, 1, 65536, R::kShapes,
                      "hemisphere rays per receiver basis function (Eq. 16)"),
      integer_setting("bounces", 16, 1, 1000, R::kLighting,
                      "bounces at most, the first included (the series runs when lighting)"),
      integer_setting("direct_samples", 4, 1, 65536, R::kLighting,
                      "direct-light samples per sender point (16 times this where the world is "
                      "an image)"),
      number_setting("sender_cutoff", 1e-3, 0.0, 1.0, R::kLighting,
                     "lighting skips senders whose projected direct light is below this "
                     "fraction of the largest (§3.3)"),
      integer_setting("visibility", 1, 0, 1, R::kShapes,
                      "1: at bake points, leave out basis functions whose point the bake point "
                      "cannot see (occlusion rays); 0: plain Eq. 6"),
      text_setting("viewpoint", "", {}, R::kShapes,
                   "\"x,y,z\": importance particles start there; empty: they leave the bake "
                   "points"),
      text_setting("cache_dir", "", {}, R::kExecution,
                   "a folder (UTF-8, created if missing): the precomputation is saved there and "
                   "a later bake of the same geometry, materials, settings (and bake points, "
                   "without a viewpoint) loads it; report \"meshless_cache\" says hit, miss, "
                   "stale or off; empty: no cache"),
      cache_size_setting(),
  };
  return specs;
}

namespace {

std::unique_ptr<Solver> make_meshless() {
  return std::make_unique<MeshlessSolver>();
}

const MethodRegistration kRegistration(
    {"meshless",
     "Meshless hierarchical basis with precomputed direct-to-indirect transfer (Lehtinen et al. "
     "2008); relights in milliseconds.",
     40, true, make_meshless, MeshlessSolver::setting_specs});

}  // namespace

}  // namespace bakegi
