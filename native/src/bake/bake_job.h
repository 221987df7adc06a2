// A bake running on its own thread: validate the scene, build the BVH, solve, evaluate at
// the bake points. Holds its own copies of scene, points and settings; progress, stage and
// cancel are safe to use from any thread while it runs.
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <glm/glm.hpp>

#include "bake/error_probes.h"
#include "field/indirect_field.h"
#include "grid/grid_gather.h"
#include "grid/irradiance_vector_grid.h"
#include "lights/lamp_shadow_cache.h"
#include "scene/bake_points.h"
#include "scene/scene.h"
#include "settings/settings.h"
#include "util/job_context.h"
#include "util/memory_budget.h"

namespace bakegi {

class Solver;
class Precomputation;
struct ErrorEstimate;
class RayTracer;
class DirectLight;
struct Scene;

// What a finished bake leaves for relighting: its scene and BVH, and the solver's
// precomputation, made with `settings` by `method`. Immutable; shared between jobs.
struct JobPrecomputation {
  std::string method;
  Settings settings;
  std::shared_ptr<const Scene> scene;
  std::shared_ptr<const RayTracer> tracer;
  std::shared_ptr<const Precomputation> solver;
};

// A grid bake (grid/): the solver's light gathered into an Irradiance Vector Grid instead
// of evaluated at bake points.
struct GridRequest {
  GridLayout layout;
  GridGatherOptions gather;  // its seed and ray epsilon are the job's
};

class BakeJob {
 public:
  // Checks the settings against the method's schema (the method name, keys the method does
  // not read, types, ranges, choices) and throws Error(INVALID_ARGUMENT) before anything
  // starts; then starts the thread.
  // `display_probes` (checked against the points) add probes inside faces to the job's
  // estimate of its own error (bake/error_estimate.h).
  BakeJob(SceneDescription description, BakePoints points, Settings settings,
          ErrorProbes display_probes = {});
  // A grid bake: solves as above, then gathers the grid (grid/grid_gather.h) and fills its
  // vertices inside geometry (grid/grid_push_pull.h); grid() holds it after success.
  BakeJob(SceneDescription description, GridRequest grid, Settings settings);
  // A relight: bakes `description`, which must have the same geometry and materials as the
  // previous bake's scene (only lights and world may differ; checked when the job runs), at
  // `points` with the previous bake's settings, reusing its precomputation. `overrides` may
  // change the settings whose role in the method's schema is lighting or execution; another
  // key with another value is refused (Error INVALID_ARGUMENT).
  BakeJob(SceneDescription description, BakePoints points,
          std::shared_ptr<const JobPrecomputation> previous, const Settings& overrides = {});
  // Cancels if still running and waits for the thread.
  ~BakeJob();
  BakeJob(const BakeJob&) = delete;
  BakeJob& operator=(const BakeJob&) = delete;

  double progress() const { return context_.progress(); }
  std::string stage() const { return context_.stage(); }
  // A cancel that reaches the job before it has ended makes it end cancelled, also when its
  // work was complete by then (its last stage no longer polled); after the end it does
  // nothing.
  void cancel();
  bool is_done() const;
  // Blocks until the job ends; returns its status and (if failed) its message.
  bakegi_status wait(std::string& message);
  // After the job ended.
  bakegi_status status() const;
  std::string error() const;
  const std::vector<glm::vec3>& results() const { return results_; }
  size_t point_count() const { return points_.size(); }
  std::string report_json() const;
  // After success, for methods that can relight: what a relight job reuses; else null.
  std::shared_ptr<const JobPrecomputation> precomputation() const;
  // After a successful grid bake, the grid; else null.
  std::shared_ptr<const IrradianceVectorGrid> grid() const;
  // The points the job bakes (a relight may reuse them).
  const BakePoints& points() const { return points_; }

  // Bytes a bake is expected to need (flattened scene, BVH, points and results, the
  // denoiser's and the irradiance cache's work), before any of it is allocated. `denoise`:
  // the denoiser's neighbourhoods are made (to filter, or to read the noise's scale).
  static size_t estimate_memory(const SceneDescription& description, size_t point_count,
                                bool denoise = false, bool irradiance_cache = false);

 private:
  void run() noexcept;
  void start();
  void execute();
  // Validates the description, builds the scene (and the BVH unless relighting) and solves.
  // Validates and flattens the description into scene_, with its counts in the report.
  const Scene& build_scene_and_report(Report& report, std::chrono::steady_clock::time_point start);
  std::unique_ptr<IndirectField> solve_full(Report& report);
  // field.evaluate(), filtered when "denoise" is set and the field estimates its noise
  // (bake/point_denoiser.h).
  void evaluate_field(const IndirectField& field, const BakePoints& points,
                      std::span<glm::vec3> out, Report& report);
  // Gathers the grid of grid_request_ from the field.
  void gather_grid_from(const IndirectField& field, Report& report);
  // Path-traces probes on the surfaces in the grid's box and compares the grid's reading
  // there (bake/error_estimate.h); warns above 10%.
  void estimate_grid_error(const IrradianceVectorGrid& grid, uint64_t seed, Report& report);
  // The report's error_estimate, estimated_error, its interval and seconds.
  void report_error_estimate(const ErrorEstimate& estimate, Report& report,
                             std::chrono::steady_clock::time_point start);
  std::unique_ptr<IndirectField> solve_relight(Report& report);
  // Path-traces probes and compares the results there (settings error_probes,
  // error_probe_samples); writes error_estimate, estimated_error and its interval.
  void estimate_error(Report& report);
  // The budget handed to the solver: memory_budget_mb with what the job holds counted.
  MemoryBudget solver_memory() const;
  // What the job holds while the solver runs: the description, the flattened scene's
  // triangles, the points and results, and the ray tracer.
  size_t held_bytes() const;
  // Full bakes of every method but "direct" check themselves; relights stay fast.
  bool wants_error_estimate() const;
  void finish(bakegi_status status, std::string message) noexcept;

  SceneDescription description_;
  BakePoints points_;
  ErrorProbes display_probes_;
  Settings settings_;
  std::unique_ptr<Solver> solver_;
  std::shared_ptr<const JobPrecomputation> previous_;     // relight jobs only
  std::shared_ptr<const JobPrecomputation> precomputed_;  // set on success, guarded by mutex_
  // What the field may refer to until it has been evaluated; released after that.
  std::shared_ptr<const Scene> scene_;
  std::shared_ptr<const RayTracer> tracer_;
  std::unique_ptr<const DirectLight> direct_;
  std::unique_ptr<const LampShadowCache> shadow_cache_;  // read by direct_
  std::string method_;
  int threads_ = 0;
  int64_t error_probes_ = 0;
  bool denoise_ = false;
  // The path tracer to a target error: without the denoiser it still reads the noise's
  // scale through the denoiser's neighbourhoods (bake_job.cpp, DenoiserOnDemand).
  bool samples_to_target_ = false;
  bool irradiance_cache_ = false;      // the path tracer's irradiance_cache > 0
  bool shadow_cache_setting_ = false;  // setting shadow_cache (the path tracer)
  int64_t error_probe_samples_ = 0;
  size_t memory_budget_bytes_ = 0;
  // A solver that cannot model the scene within the memory budget hands the bake to the path
  // tracer (setting "fallback", default 1) instead of failing it: see solve_full.
  bool fallback_ = true;
  std::unique_ptr<Settings> fallback_settings_;  // the path tracer's, alive as long as its field

  JobContext context_;
  std::vector<glm::vec3> results_;
  std::optional<GridRequest> grid_request_;
  std::shared_ptr<const IrradianceVectorGrid> grid_;  // set on success, guarded by mutex_

  mutable std::mutex mutex_;
  std::condition_variable done_changed_;
  bool done_ = false;
  bakegi_status status_ = BAKEGI_OK;
  std::string error_;
  std::thread thread_;
};

}  // namespace bakegi
