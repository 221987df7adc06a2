// One interface for every method of DESIGN.md (pathtrace, antiradiance, meshless, ivg,
// splatting). make_solver() in solver_registry.cpp picks one by the "method" setting.
#pragma once

#include <memory>
#include <string>

#include "field/indirect_field.h"

namespace bakegi {

struct Scene;
class RayTracer;
class Settings;
class JobContext;
class DirectLight;

struct SolveInputs {
  const Scene& scene;
  const RayTracer& tracer;
  const DirectLight& direct;
  const Settings& settings;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) = 0;
};

// Throws bakegi::Error(INVALID_ARGUMENT) for an unknown method name.
std::unique_ptr<Solver> make_solver(const std::string& method);

}  // namespace bakegi
