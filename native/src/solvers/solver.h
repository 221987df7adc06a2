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

class Solver {
 public:
  virtual ~Solver() = default;
  // A full solve. A method that can relight keeps its precomputation for precomputation().
  virtual std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) = 0;

  // Whether relight() works for this method.
  virtual bool can_relight() const { return false; }
  // The precomputation of the last successful solve(), or null.
  virtual std::shared_ptr<const Precomputation> precomputation() const { return nullptr; }
  // Solves again with the lights of inputs.scene, reusing `reuse` (made by a solver of the same
  // method from a scene with the same geometry and materials and the same settings; the caller
  // checks that). Throws Error(INVALID_ARGUMENT) for methods that cannot relight.
  virtual std::unique_ptr<IndirectField> relight(const SolveInputs& inputs,
                                                 const Precomputation& reuse, JobContext& context);
};

}  // namespace bakegi
