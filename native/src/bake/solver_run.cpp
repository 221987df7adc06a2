#include "bake/solver_run.h"

#include "bake/precomputation_store.h"
#include "settings/settings.h"
#include "solvers/precomputation_codec.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/report.h"

namespace bakegi {

namespace {

// The precomputation, from the cache when the method has one and a folder is set.
std::shared_ptr<const Precomputation> precompute_or_load(Solver& solver, const std::string& method,
                                                         const SolveInputs& inputs,
                                                         JobContext& context) {
  const PrecomputationCodec* codec = solver.codec();
  const SettingSchema& schema = method_schema(method);
  if (codec == nullptr || schema.find("cache_dir") == nullptr) {
    return solver.precompute(inputs, context);
  }
  const SettingReader reader(inputs.settings, schema);
  const std::string folder = reader.get_string("cache_dir");
  if (folder.empty()) {
    context.report().set_text(codec->name() + "_cache", "off");
    return solver.precompute(inputs, context);
  }
  // Everything that shapes the precomputation: the settings read so far (check_settings
  // read every key of the method, with defaults) except those whose role is lighting or
  // execution.
  std::vector<std::string> ignored = schema.keys_with_role(SettingRole::kLighting);
  for (const std::string& key : schema.keys_with_role(SettingRole::kExecution)) {
    ignored.push_back(key);
  }
  const CacheRequest request{*codec, folder, inputs.scene.description, inputs.settings,
                             std::move(ignored),
                             codec->keyed_by_points(inputs.settings) ? inputs.points : nullptr,
                             // The file cannot hold more than the precomputation may take.
                             inputs.memory.total(), uint64_t(reader.get_int("cache_max_mb")) << 20};
  return load_or_precompute(request, context, [&] { return solver.precompute(inputs, context); });
}

}  // namespace

SolverRun run_solver(Solver& solver, const std::string& method, const SolveInputs& inputs,
                     JobContext& context) {
  solver.check_settings(inputs.settings);
  SolverRun run;
  if (!solver.has_precomputation()) {
    run.field = solver.solve(inputs, context);
    return run;
  }
  run.precomputation = precompute_or_load(solver, method, inputs, context);
  run.field = solver.light(inputs, run.precomputation, context);
  return run;
}

std::unique_ptr<IndirectField> relight_solver(Solver& solver, const SolveInputs& inputs,
                                              std::shared_ptr<const Precomputation> kept,
                                              JobContext& context) {
  if (!solver.has_precomputation()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "this method keeps no precomputation and cannot relight; start a full bake");
  }
  solver.check_settings(inputs.settings);
  return solver.light(inputs, std::move(kept), context);
}

}  // namespace bakegi
