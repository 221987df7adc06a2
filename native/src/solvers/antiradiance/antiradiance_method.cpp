// Antiradiance as a method: its registration and its settings. Lighting: what a relight may
// change (relighting without relinking, §3.3: bins, hierarchy and links stay); the rest
// shapes them and is part of the precomputation cache's key.
#include "bake/precomputation_store.h"
#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/method_registry.h"

namespace bakegi {

const std::vector<SettingSpec>& AntiradianceSolver::setting_specs() {
  using R = SettingRole;
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  static const std::vector<SettingSpec> specs = {
      integer_setting("bins", 300, 12, 3072, R::kShapes,
                      "directional bins (rounded to a HEALPix count, 12 Nside^2)"),
      integer_setting("iterations", 32, 1, 100000, R::kLighting, "bounces at most"),
      number_setting("tolerance", 1e-4, 0.0, 1.0, R::kLighting,
                     "stop when a bounce adds less than this fraction"),
      text_setting("scheme", "symmetric", {"symmetric", "asymmetric"}, R::kLighting,
                   "iteration scheme (§2.2): asymmetric is provably convergent"),
      number_setting("patch_size", 0.0, 0.0, 1e9, R::kShapes,
                     "largest patch edge in metres; 0 = automatic (scene extent / 16, coarsened "
                     "to fit the memory budget, with a warning)"),
      integer_setting("direct_samples", 64, 1, 65536, R::kLighting,
                      "direct-light samples per patch"),
      integer_setting("seed", 0, 0, kMax, R::kLighting,
                      "random seed; picks the direct-light samples of the patches"),
      text_setting("oracle", "sphere", {"sphere", "projected"}, R::kShapes,
                   "how linking measures an element's solid angle: its bounding sphere's disk, "
                   "or its projected area (3-6x fewer links, a little more error)"),
      number_setting("oracle_factor", 1.0, 0.05, 64.0, R::kShapes,
                     "refine links while an end subtends more than this many bins (1: the "
                     "paper's criterion)"),
      number_setting("glossy_fold_exponent", 16.0, 0.0, 1e6, R::kShapes,
                     "glossy lobes with a lower exponent reflect as diffuse (energy kept; 16 is "
                     "roughness above about 0.42; 0 keeps every lobe)"),
      integer_setting("near_field_rays", 256, 0, 65536, R::kShapes,
                      "bake points near another surface gather this many rays from the solution "
                      "instead of interpolating patches; 0 = interpolate everywhere"),
      number_setting("near_field_distance", 0.5, 0.0, 100.0, R::kShapes,
                     "\"near\" in units of the interpolation's support radius (about two patch "
                     "edges); blended over its last half"),
      text_setting("residual", "off", {"off", "path_traced"}, R::kLighting,
                   "off: interpolate the solution (fast, biased where it is wrong); path_traced: "
                   "path-trace with the solution as control variate (unbiased: the path "
                   "tracer's sampling settings apply, the solution only saves samples)"),
      number_setting("residual_fraction", 0.0, 0.0, 1.0, R::kLighting,
                     "with residual = path_traced: the fraction of paths that go on beyond "
                     "the first hit's light sample; 0 = chosen by a pilot"),
      text_setting("cache_dir", "", {}, R::kExecution,
                   "a folder (UTF-8, created if missing): the hierarchy and links are saved "
                   "there and a later bake of the same geometry, materials and settings loads "
                   "them; report \"antiradiance_cache\" says hit, miss, stale or off; empty: no "
                   "cache"),
      cache_size_setting(),
  };
  return specs;
}

namespace {

std::unique_ptr<Solver> make_antiradiance() {
  return std::make_unique<AntiradianceSolver>();
}

const MethodRegistration kRegistration(
    {"antiradiance",
     "Antiradiance (Dachsbacher et al. 2007): hierarchical transport without visibility rays, "
     "interpolated at the bake points; relights without relinking.",
     30, true, make_antiradiance, AntiradianceSolver::setting_specs});

}  // namespace

}  // namespace bakegi
