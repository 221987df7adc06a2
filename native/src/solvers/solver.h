// One interface for every method. Each solver folder registers its method
// (method_registry.h); make_solver() picks one by the "method" setting.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "field/indirect_field.h"
#include "settings/setting_schema.h"
#include "solvers/method_registry.h"
#include "util/memory_budget.h"

namespace bakegi {

struct Scene;
class RayTracer;
class Settings;
class JobContext;
class DirectLight;

// The budget of memory_budget_mb with the ray tracer held: what a solver called outside a
// job (tests, benchmarks) gets; a job hands down its own, which also holds its scene and points.
MemoryBudget memory_budget_for(const Settings& settings, const RayTracer& tracer);

struct SolveInputs {
  const Scene& scene;
  const RayTracer& tracer;
  const DirectLight& direct;
  const Settings& settings;
  // The job's bake points, for methods that place their own samples where the bake needs
  // them (meshless); null when not known. The field is still evaluated at whatever points
  // its evaluate() receives.
  const BakePoints* points = nullptr;
  // What the solver's own structures may take: memory.remaining() (the job has counted what
  // it holds). Solvers size patches, links and caches from it and refuse beyond it.
  MemoryBudget memory = memory_budget_for(settings, tracer);
};

// What a method computed from geometry, materials and settings alone, so that a later bake
// with other lights can skip it ("relighting without relinking", Antiradiance §3.3).
// Jobs share it (shared_ptr to const). What it holds is fixed when made, except caches
// derived from it on first use (meshless: the visible relations and evaluation weights, made
// under a mutex for the bake points that need them).
class Precomputation {
 public:
  virtual ~Precomputation() = default;
  virtual size_t memory_bytes() const = 0;
};

class PrecomputationCodec;

// One lifecycle for every method: precompute -> light -> field. A method with a
// precomputation (what geometry, materials and the "shapes" settings alone decide) overrides
// precompute() and light(); the job then keeps the precomputation for relights, and caches it
// on disk when the method also has a codec() and a "cache_dir" setting
// (bake/precomputation_store.h). A method without one overrides solve() only.
class Solver {
 public:
  virtual ~Solver() = default;

  // Reads every setting of the method, so that a bad value fails before any work (and the
  // settings a cache key names are the ones read).
  virtual void check_settings(const Settings&) const {}
  // Whether precompute() and light() are implemented (and so relights work).
  virtual bool has_precomputation() const { return false; }
  virtual std::shared_ptr<const Precomputation> precompute(const SolveInputs& inputs,
                                                           JobContext& context);
  // Lights `precomputation` (made by this method, for a scene with the same geometry and
  // materials and the same "shapes" settings; the job checks that) with inputs.scene's
  // lights. The field may keep the precomputation alive.
  virtual std::unique_ptr<IndirectField> light(
      const SolveInputs& inputs, std::shared_ptr<const Precomputation> precomputation,
      JobContext& context);
  // How the precomputation is saved and loaded, or null (no cache).
  virtual const PrecomputationCodec* codec() const { return nullptr; }

  // A full solve: light(precompute()) for methods with a precomputation.
  virtual std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context);
};

}  // namespace bakegi
