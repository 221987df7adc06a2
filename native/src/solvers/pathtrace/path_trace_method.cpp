// The path tracer as a method: its registration and its own settings (the sampling ones are
// common: settings/setting_schema.cpp).
#include "solvers/method_registry.h"
#include "solvers/pathtrace/path_trace_solver.h"

namespace bakegi {

const std::vector<SettingSpec>& PathTraceSolver::setting_specs() {
  static const std::vector<SettingSpec> specs = {
      integer_setting("max_bounces", 64, 1, 1 << 16, SettingRole::kShapes,
                      "path length cap for indirect light (Russian roulette ends most paths far "
                      "sooner)"),
      number_setting("target_error", 0.0, 0.0, 1.0, SettingRole::kLighting,
                     "error to reach: NRMSE over the bake points as the samples' spread "
                     "predicts it (an upper bound with quasi-random samples); samples go where "
                     "the noise is, `samples` caps each point; 0 = exactly `samples` per point"),
      number_setting("irradiance_cache", 0.0, 0.0, 1.0, SettingRole::kLighting,
                     "accuracy a of an irradiance cache (Ward & Heckbert; docs/methods/"
                     "pathtrace.md): `samples` paths (>= 256; a cap with target_error) at "
                     "sparse records, the other points interpolated with gradients; smaller a "
                     "places records closer "
                     "(0.2-0.3 measured best, docs/benchmarks.md 0g); with target_error the "
                     "records sample in rounds; declines (warning) where over half the points "
                     "would be records; 0 = off"),
      integer_setting("shadow_cache", 1, 0, 1, SettingRole::kLighting,
                      "1: a pilot of shadow rays finds where each lamp is blocked (a grid of "
                      "cells over the scene, lights/lamp_shadow_cache.h), and there a lamp's "
                      "shadow ray is traced only for 1 light sample in 8, weighed 8x: unbiased, "
                      "about a fifth fewer rays and a tenth less time where the sun or a lamp "
                      "is blocked from most places (docs/benchmarks.md 0m); 0: every shadow "
                      "ray traced"),
  };
  return specs;
}

namespace {

std::unique_ptr<Solver> make_pathtrace() {
  return std::make_unique<PathTraceSolver>();
}

const MethodRegistration kRegistration({"pathtrace",
                                        "Monte Carlo path tracing: the reference (DESIGN.md).", 10,
                                        false, make_pathtrace, PathTraceSolver::setting_specs});

}  // namespace

}  // namespace bakegi
