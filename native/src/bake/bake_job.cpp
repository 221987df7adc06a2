#include "bake/bake_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>

#include <tbb/task_arena.h>

#include "bake/error_estimate.h"
#include "bake/point_denoiser.h"
#include "bake/point_sharing.h"
#include "bake/settings_check.h"
#include "bake/solver_run.h"
#include "grid/grid_error_probes.h"
#include "grid/grid_hit_radiance.h"
#include "grid/grid_push_pull.h"
#include "grid/grid_visibility.h"
#include "lights/direct_light.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "solvers/pathtrace/irradiance_cache_bake.h"
#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {

namespace {

// Embree's copies of vertices (36 bytes) and indices (12) per triangle plus its BVH built
// with RTC_BUILD_QUALITY_HIGH: about 112 bytes per triangle in all on a regular grid
// (test_ray_tracer); spatial splits duplicate references on irregular meshes, hence the
// headroom.
constexpr size_t kEmbreeBytesPerTriangle = 48 + 160;
constexpr size_t kBytesPerPoint = sizeof(glm::vec3) * 2 + sizeof(uint32_t);
constexpr size_t kBytesPerResult = sizeof(glm::vec3);
// Paths per bake point when a bake falls back to the path tracer (solve_full): twice the
// add-on's default of 64 (about 13% noise on the Cornell box); the error estimate says more.
constexpr int64_t kFallbackSamples = 128;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Above this estimated NRMSE a grid bake warns (the add-on's error check flags bakes at the
// same 10%: error_check.THRESHOLD).
constexpr double kGridErrorWarning = 0.10;

std::string megabytes(size_t bytes) {
  return MemoryBudget::megabytes(bytes);
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

size_t description_bytes(const SceneDescription& d) {
  size_t bytes = d.materials.size() * sizeof(Material) + d.lights.size() * sizeof(Light);
  for (const Texture& t : d.textures) bytes += t.bytes();
  for (const Mesh& m : d.meshes) {
    bytes += m.positions.size() * sizeof(glm::vec3) + m.indices.size() * sizeof(uint32_t) +
             m.corner_normals.size() * sizeof(glm::vec3) + m.corner_uvs.size() * sizeof(glm::vec2) +
             m.triangle_materials.size() * sizeof(uint32_t);
  }
  return bytes;
}

size_t triangle_count(const SceneDescription& d) {
  size_t count = 0;
  for (const Mesh& m : d.meshes) count += m.indices.size() / 3;
  return count;
}

}  // namespace

size_t BakeJob::estimate_memory(const SceneDescription& description, size_t point_count,
                                bool denoise, bool irradiance_cache) {
  // The Scene holds a second copy of the description next to its triangles.
  return description_bytes(description) + estimate_scene_bytes(description) +
         triangle_count(description) * kEmbreeBytesPerTriangle +
         point_count * (kBytesPerPoint + kBytesPerResult + (denoise ? kDenoiseBytesPerPoint : 0) +
                        (irradiance_cache ? kIrradianceCacheBytesPerPoint : 0));
}

BakeJob::BakeJob(SceneDescription description, BakePoints points, Settings settings,
                 ErrorProbes display_probes)
    : description_(std::move(description)),
      points_(std::move(points)),
      display_probes_(std::move(display_probes)),
      settings_(std::move(settings)) {
  check_error_probes(display_probes_, points_.size());
  start();
}

BakeJob::BakeJob(SceneDescription description, GridRequest grid, Settings settings)
    : description_(std::move(description)),
      settings_(std::move(settings)),
      grid_request_(std::move(grid)) {
  if (grid_request_->layout.vertex_count() == 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "the grid has no vertices");
  }
  start();
}

BakeJob::BakeJob(SceneDescription description, BakePoints points,
                 std::shared_ptr<const JobPrecomputation> previous, const Settings& overrides)
    : description_(std::move(description)), points_(std::move(points)) {
  if (!previous || !previous->solver || !previous->scene || !previous->tracer) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "the previous bake left nothing to relight from (it failed, was cancelled, or "
                "its method cannot relight)");
  }
  settings_ = previous->settings;
  const SettingSchema& schema = method_schema(previous->method);
  for (const auto& [key, value] : overrides.values()) {
    const SettingSpec* spec = schema.find(key);
    const bool allowed = spec != nullptr && spec->role != SettingRole::kShapes;
    const auto before = settings_.values().find(key);
    const bool same = before != settings_.values().end() && before->second == value;
    if (!allowed && !same) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "setting \"" + key + "\" shaped the bake that is relit and cannot change in a " +
                      "relight; start a full bake");
    }
    settings_.set(key, value);
  }
  previous_ = std::move(previous);
  start();
}

void BakeJob::start() {
  // The method picks the schema; every given value is then checked at once (before any work).
  method_ = validated_method(settings_);
  const SettingSchema& schema = method_schema(method_);
  const SettingReader settings(settings_, schema);
  settings.get_string("method");  // remembered: the report and cache keys name the method
  threads_ = int(settings.get_int("threads"));
  error_probes_ = settings.get_int("error_probes");
  denoise_ = settings.get_int("denoise") != 0;
  irradiance_cache_ = method_ == "pathtrace" && settings.get_float("irradiance_cache") > 0.0;
  samples_to_target_ = method_ == "pathtrace" && settings.get_float("target_error") > 0.0;
  shadow_cache_setting_ = method_ == "pathtrace" && settings.get_int("shadow_cache") != 0;
  error_probe_samples_ = settings.get_int("error_probe_samples");
  memory_budget_bytes_ = size_t(settings.get_int("memory_budget_mb")) << 20;
  fallback_ = settings.get_int("fallback") != 0;
  solver_ = make_solver(method_);
  if (previous_ && !solver_->has_precomputation()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "method '" + method_ + "' cannot relight; start a full bake");
  }

  context_.report().set_text("method", method_);
  context_.report().set_number("relight", previous_ ? 1.0 : 0.0);
  context_.report().add_count("bake_points", points_.size());
  context_.report().add_count("rays", 0);
  context_.set_stage("queued", 0.0, 0.0);
  thread_ = std::thread([this] { run(); });
}

BakeJob::~BakeJob() {
  cancel();
  try {
    if (thread_.joinable()) thread_.join();
  } catch (...) {
    // join fails only if the thread is gone already; nothing is left to wait for.
  }
}

void BakeJob::cancel() {
  std::lock_guard lock(mutex_);
  if (!done_) context_.cancel();
}

bool BakeJob::is_done() const {
  std::lock_guard lock(mutex_);
  return done_;
}

bakegi_status BakeJob::wait(std::string& message) {
  std::unique_lock lock(mutex_);
  done_changed_.wait(lock, [this] { return done_; });
  message = error_;
  return status_;
}

bakegi_status BakeJob::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

std::string BakeJob::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

std::string BakeJob::report_json() const {
  return context_.report().to_json();
}

std::shared_ptr<const JobPrecomputation> BakeJob::precomputation() const {
  std::lock_guard lock(mutex_);
  return precomputed_;
}

void BakeJob::run() noexcept {
  try {
    execute();
    finish(BAKEGI_OK, "");
  } catch (const Error& e) {
    finish(e.status(), e.what());
  } catch (const std::bad_alloc&) {
    finish(BAKEGI_ERROR_OUT_OF_MEMORY, "out of memory during the bake");
  } catch (const std::exception& e) {
    finish(BAKEGI_ERROR_INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    finish(BAKEGI_ERROR_INTERNAL, "internal error");
  }
}

void BakeJob::execute() {
  Report& report = context_.report();
  const auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(threads_ == 0 ? tbb::task_arena::automatic : threads_);
  report.add_count("threads", uint64_t(arena.max_concurrency()));

  arena.execute([&] {
    const std::unique_ptr<IndirectField> field =
        previous_ ? solve_relight(report) : solve_full(report);
    if (!field) throw Error(BAKEGI_ERROR_INTERNAL, "solver '" + method_ + "' returned no field");
    context_.throw_if_cancelled();
    if (grid_request_) {
      gather_grid_from(*field, report);
      return;
    }

    // Whatever part of the solve range the solver did not report is skipped, so progress
    // runs on smoothly from where it stands.
    const bool estimate = wants_error_estimate();
    context_.set_stage("evaluating", context_.progress(), estimate ? 0.95 : 1.0);
    const auto stage_start = std::chrono::steady_clock::now();
    const SharedPoints shared = share_points(points_, *tracer_, direct_->ray_epsilon());
    if (shared.distinct_index.empty()) {
      results_.assign(points_.size(), glm::vec3(0.0f));
      evaluate_field(*field, points_, results_, report);
    } else {
      // Corners of one vertex in one light are evaluated once (bake/point_sharing.h).
      std::vector<glm::vec3> distinct(shared.distinct.size(), glm::vec3(0.0f));
      evaluate_field(*field, shared.distinct, distinct, report);
      spread_shared_values(shared, distinct, results_);
    }
    report.add_count("evaluated_points",
                     shared.distinct_index.empty() ? points_.size() : shared.distinct.size());
    context_.throw_if_cancelled();
    for (size_t i = 0; i < results_.size(); ++i) {
      const glm::vec3& v = results_[i];
      if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z))) {
        throw Error(BAKEGI_ERROR_INTERNAL, "solver '" + method_ +
                                               "' produced a non-finite value at bake point " +
                                               std::to_string(i));
      }
    }
    report.add_seconds("evaluate", seconds_since(stage_start));
    if (estimate) estimate_error(report);
  });
  report.add_seconds("total", seconds_since(start));
}

namespace {

// The denoiser as the filter an adaptive sampler aims through: its neighbourhoods (rays) are
// found when the sampler first asks, or after the evaluation, so that a field without noise
// estimates costs nothing. With `filters` false the bake keeps its raw means and the denoiser
// only reads, each round, how much their variances overstate their noise
// (PointDenoiser::noise_scale), so that a bake to a target error stops where its means meet
// it rather than where their variances say they do (Owen-scrambled samples: 0.54-0.75 of it
// in variance on the suite).
class DenoiserOnDemand : public NoiseFilter {
 public:
  DenoiserOnDemand(const BakePoints& points, const RayTracer& tracer, float ray_epsilon,
                   bool filters)
      : points_(points), tracer_(tracer), ray_epsilon_(ray_epsilon), filters_(filters) {}

  FilteredNoise predict(std::span<const glm::vec3> values, std::span<const float> variance_of_mean,
                        JobContext& context) const override {
    const PointDenoiser& denoiser = get(context, /*report_progress=*/false);
    FilteredNoise predicted;
    seconds_ += timed([&] {
      if (filters_) {
        predicted = denoiser.predict(values, variance_of_mean, context);
      } else {
        predicted.noise_left = std::sqrt(denoiser.noise_scale(values, variance_of_mean, context));
      }
    });
    return predicted;
  }
  bool changes_values() const override { return filters_; }

  const PointDenoiser& get(JobContext& context, bool report_progress = true) const {
    if (!denoiser_) {
      seconds_ += timed(
          [&] { denoiser_.emplace(points_, tracer_, ray_epsilon_, context, report_progress); });
    }
    return *denoiser_;
  }
  bool made() const { return denoiser_.has_value(); }
  double seconds() const { return seconds_; }

 private:
  template <typename Work>
  static double timed(Work work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    return seconds_since(start);
  }

  const BakePoints& points_;
  const RayTracer& tracer_;
  float ray_epsilon_;
  bool filters_;
  mutable std::optional<PointDenoiser> denoiser_;
  mutable double seconds_ = 0.0;
};

}  // namespace

void BakeJob::gather_grid_from(const IndirectField& field, Report& report) {
  const GridLayout& layout = grid_request_->layout;
  const size_t bytes =
      IrradianceVectorGrid::bytes_for(layout.vertex_count(), grid_gathers_emitted(*scene_));
  const MemoryBudget budget = solver_memory();
  if (bytes > budget.remaining()) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, "the grid of " + std::to_string(layout.vertex_count()) +
                                                " vertices needs " + megabytes(bytes) +
                                                ", more than the " + megabytes(budget.remaining()) +
                                                " left of the budget of " + budget.describe() +
                                                "; use larger cells or fewer vertices");
  }
  context_.set_stage("gathering the grid", context_.progress(), 1.0);
  const auto start = std::chrono::steady_clock::now();
  GridGatherOptions options = grid_request_->gather;
  options.seed = uint64_t(SettingReader(settings_, method_schema(method_)).get_int("seed"));
  options.ray_epsilon = direct_->ray_epsilon();
  const std::unique_ptr<HitRadiance> radiance = make_hit_radiance(*direct_, field);
  GridGatherStatistics statistics;
  auto grid = std::make_shared<IrradianceVectorGrid>(
      gather_grid(layout, *scene_, *tracer_, *radiance, options, context_, statistics));
  const size_t filled = fill_invalid_vertices(*grid);
  report.add_count("rays", statistics.rays);
  report.add_count("grid_vertices", layout.vertex_count());
  report.add_count("grid_invalid_vertices", statistics.invalid_vertices);
  report.add_count("grid_filled_vertices", filled);
  report.add_count("grid_rays_per_hemisphere", options.rays_per_hemisphere);
  report.set_json("grid_resolution", "[" + std::to_string(layout.resolution[0]) + ", " +
                                         std::to_string(layout.resolution[1]) + ", " +
                                         std::to_string(layout.resolution[2]) + "]");
  report.add_seconds("grid_gather", seconds_since(start));
  if (error_probes_ > 0) estimate_grid_error(*grid, options.seed, report);
  if (statistics.invalid_vertices == layout.vertex_count()) {
    report.warn(
        "grid: every vertex lies inside geometry (its rays hit back faces); the grid "
        "is black. Check the grid's bounds against the scene");
  }
  std::lock_guard lock(mutex_);
  grid_ = std::move(grid);
}

void BakeJob::estimate_grid_error(const IrradianceVectorGrid& grid, uint64_t seed, Report& report) {
  context_.set_stage("estimating the error", context_.progress(), 1.0);
  const auto start = std::chrono::steady_clock::now();
  ErrorEstimateSettings settings;
  settings.samples = error_probe_samples_;
  settings.seed = seed;
  const ErrorProbes probes =
      grid_surface_probes(*scene_, grid.layout, size_t(error_probes_), settings.seed);
  if (probes.size() == 0) {
    report.warn("grid: no surface lies inside its box, so its error could not be estimated");
    return;
  }
  // The grid as Apply Grid reads it by default (grid_visibility.h, |n| weights).
  GridSceneLookup lookup;
  lookup.weights = GridDirectionalWeights::kAbsolute;
  std::vector<glm::vec3> values(probes.size());
  GridSceneStatistics statistics;
  evaluate_grid_in_scene(grid, *scene_, *tracer_, probes.points.positions, probes.points.normals,
                         lookup, values, {}, statistics);
  report.add_count("error_probe_rays", statistics.rays);
  const ErrorEstimate estimate =
      bakegi::estimate_error(*direct_, probes, ErrorProbes{}, values, settings, context_);
  report_error_estimate(estimate, report, start);
  const ProbeErrorStatistics& e = estimate.at_points;
  if (e.nrmse > kGridErrorWarning) {
    report.warn("grid: Apply Grid's light is about " + percent(e.nrmse) +
                " (90%: " + percent(e.low) + " to " + percent(e.high) +
                ") off the path tracer's at " + std::to_string(e.probes) +
                " points on the surfaces in its box. Smaller cells and more rays lower it; "
                "light that changes within a cell (sun patches, corners, contact shadows) the "
                "grid cannot hold: bake those surfaces directly");
  }
}

std::shared_ptr<const IrradianceVectorGrid> BakeJob::grid() const {
  std::lock_guard lock(mutex_);
  return grid_;
}

void BakeJob::evaluate_field(const IndirectField& field, const BakePoints& points,
                             std::span<glm::vec3> out, Report& report) {
  if (!denoise_) {
    if (!samples_to_target_) {
      field.evaluate(points, out, context_);
      return;
    }
    std::vector<float> variance(points.size(), 0.0f);
    const DenoiserOnDemand scale(points, *tracer_, direct_->ray_epsilon(), /*filters=*/false);
    field.evaluate_with_variance(points, out, variance, &scale, context_);
    if (scale.made()) {
      report.add_seconds("noise_scale", scale.seconds());
      report.add_count("rays", scale.get(context_).rays());
    }
    return;
  }
  std::vector<float> variance(points.size(), 0.0f);
  const DenoiserOnDemand denoiser(points, *tracer_, direct_->ray_epsilon(), /*filters=*/true);
  if (!field.evaluate_with_variance(points, out, variance, &denoiser, context_)) {
    report.warn("denoise: this method's result has no noise estimates and is not filtered");
    return;
  }
  context_.throw_if_cancelled();
  context_.set_stage_text("denoising");
  const PointDenoiser& filter = denoiser.get(context_);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<glm::vec3> raw(out.begin(), out.end());
  const DenoiseStatistics statistics = filter.filter(out, variance, context_);
  // Where the bias it adds outweighs the noise it takes out, the raw means are the better bake.
  const double bias = std::max(statistics.mean_shift, statistics.local_bias);
  const double filtered_error = std::hypot(statistics.noise_after, bias);
  const double raw_noise = statistics.noise_before * std::sqrt(statistics.variance_scale);
  const bool applied = !(raw_noise > 0.0 && filtered_error >= raw_noise);
  if (!applied) {
    std::copy(raw.begin(), raw.end(), out.begin());
    report.warn("denoise: the filter would add more error (bias " + percent(bias) +
                ") than it takes out (noise " + percent(raw_noise) + " to " +
                percent(statistics.noise_after) + "); the values are not filtered");
    // The sampler predicted the filtered error; the raw means' is their noise.
    if (report.has_number("sampling_predicted_error")) {
      report.set_number("sampling_predicted_error", raw_noise);
    }
  }
  report.set_number("denoise_applied", applied ? 1.0 : 0.0);
  // Finding the neighbourhoods and every prediction the sampler asked for count as denoising.
  report.add_seconds("denoise", seconds_since(start) + denoiser.seconds());
  report.add_count("rays", statistics.rays);
  report.set_number("denoise_noise_before", raw_noise);
  report.set_number("denoise_noise_after", statistics.noise_after);
  report.set_number("denoise_mean_shift", statistics.mean_shift);
  report.set_number("denoise_local_bias", statistics.local_bias);
  report.set_number("denoise_residual_share", statistics.residual_share);
  report.set_number("denoise_variance_scale", statistics.variance_scale);
}

const Scene& BakeJob::build_scene_and_report(Report& report,
                                             std::chrono::steady_clock::time_point start) {
  scene_ = std::make_shared<const Scene>(build_scene(description_));
  for (const std::string& warning : scene_->warnings) report.warn(warning);
  report.add_count("triangles", scene_->triangles.size());
  report.add_count("lights", scene_->description.lights.size());
  if (!scene_->description.portals.empty()) {
    report.add_count("portals", scene_->description.portals.size());
  }
  report.add_count("emissive_triangles", scene_->emissive_triangles.size());
  report.add_seconds("validate", seconds_since(start));
  context_.throw_if_cancelled();
  return *scene_;
}

std::unique_ptr<IndirectField> BakeJob::solve_full(Report& report) {
  context_.set_stage("validating", 0.0, 0.02);
  auto stage_start = std::chrono::steady_clock::now();
  const size_t estimate = estimate_memory(description_, points_.size(),
                                          denoise_ || samples_to_target_, irradiance_cache_);
  report.add_count("memory_estimate_bytes", estimate);
  if (estimate > memory_budget_bytes_) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                "the bake needs an estimated " + megabytes(estimate) + " (" +
                    std::to_string(triangle_count(description_)) + " triangles, " +
                    std::to_string(points_.size()) + " bake points), more than the budget of " +
                    megabytes(memory_budget_bytes_) + " (setting memory_budget_mb)");
  }
  const Scene& scene = build_scene_and_report(report, stage_start);

  context_.set_stage("building BVH", 0.02, 0.1);
  stage_start = std::chrono::steady_clock::now();
  RayTracerOptions options;
  const size_t other_bytes = estimate - triangle_count(description_) * kEmbreeBytesPerTriangle;
  options.memory_budget_bytes =
      memory_budget_bytes_ > other_bytes ? memory_budget_bytes_ - other_bytes : 1;
  options.progress = [this](double fraction) {
    context_.set_stage_progress(fraction);
    return !context_.is_cancelled();
  };
  tracer_ = std::make_shared<const RayTracer>(scene, options);
  report.add_seconds("bvh", seconds_since(stage_start));
  context_.throw_if_cancelled();

  context_.set_stage("solving", 0.1, 0.6);
  stage_start = std::chrono::steady_clock::now();
  {
    auto direct = std::make_unique<DirectLight>(scene, *tracer_);
    if (shadow_cache_setting_ && direct->lamp_count() > 0) {
      // The lamps' blocked places, so that the path tracer skips most shadow rays there.
      uint64_t pilot_rays = 0;
      const auto pilot_start = std::chrono::steady_clock::now();
      shadow_cache_ = std::make_unique<const LampShadowCache>(
          LampShadowCache::build(scene, *direct, pilot_rays));
      report.add_seconds("shadow_cache", seconds_since(pilot_start));
      report.add_count("shadow_cache_rays", pilot_rays);
      direct->set_shadow_cache(shadow_cache_.get());
    }
    direct_ = std::move(direct);
  }
  const SolveInputs inputs{scene, *tracer_, *direct_, settings_, &points_, solver_memory()};
  SolverRun run;
  std::string method_used = method_;
  {
    const ProgressRange solving(context_, 0.1, 0.6);  // the solver counts from 0 to 1 in it
    try {
      run = run_solver(*solver_, method_, inputs, context_);
    } catch (const Error& e) {
      // A scene too large for a hierarchical solver's model, or one its model cannot solve
      // (antiradiance diverging on a furnished room), still gets a bake the user can trust: the
      // path tracer's, whose error the estimate below states, with the reason in the warnings.
      const bool cannot_model = e.status() == BAKEGI_ERROR_OUT_OF_MEMORY ||
                                dynamic_cast<const CannotModel*>(&e) != nullptr;
      if (!cannot_model || !fallback_ || method_ == "pathtrace") throw;
      Settings fallback_settings = settings_;
      if (!settings_.has("samples")) fallback_settings.set("samples", kFallbackSamples);
      const SettingReader fallback_reader(fallback_settings, method_schema("pathtrace"));
      report.warn(std::string(e.what()) + ". Baked with the path tracer instead (" +
                  std::to_string(fallback_reader.get_int("samples")) +
                  " samples; setting fallback=0 refuses instead)");
      method_used = "pathtrace";
      solver_ = make_solver("pathtrace");
      fallback_settings_ = std::make_unique<Settings>(std::move(fallback_settings));
      const SolveInputs fallback_inputs{scene,    *tracer_,       *direct_, *fallback_settings_,
                                        &points_, solver_memory()};
      run = run_solver(*solver_, method_used, fallback_inputs, context_);
    }
  }
  report.set_text("method_used", method_used);
  const bool shadowless_light =
      std::any_of(scene.description.lights.begin(), scene.description.lights.end(),
                  [](const Light& light) { return (light.flags & BAKEGI_LIGHT_NO_SHADOW) != 0; });
  const bool spread_light = std::any_of(
      scene.description.lights.begin(), scene.description.lights.end(), [](const Light& light) {
        return light.type == BAKEGI_LIGHT_AREA && light.spot_size > 0.0f &&
               light.spot_size < std::numbers::pi_v<float>;
      });
  if (spread_light && method_used == "splatting") {
    report.warn(
        "splatting's reflective shadow maps take area lights as Lambertian emitters, also those "
        "with a spread below 180 degrees (their direct light and the other methods do not)");
  }
  if (shadowless_light && method_used == "splatting") {
    report.warn(
        "splatting's reflective shadow maps shadow every light, also those with Cast Shadow "
        "off (their direct light and the other methods do not)");
  }
  if (scene.environment && method_used == "splatting") {
    report.warn(
        "splatting lights its reflective shadow maps of the sky with the world "
        "image's mean colour, not the image (its direct light and the other methods "
        "use the image)");
  }
  if (tracer_->has_passing_surfaces() && method_used != "pathtrace" && method_used != "direct") {
    // Their rays pass glass and cut-outs, but their transport between surfaces (antiradiance's
    // links, meshless' basis, splatting's shadow maps) does not everywhere.
    report.warn(method_used +
                ": light through see-through surfaces (glass, cut-outs) is modelled only along "
                "its rays, not in all of its transport: bake such scenes with the path tracer");
  }
  report.add_seconds("solve", seconds_since(stage_start));

  std::shared_ptr<const Precomputation> kept = std::move(run.precomputation);
  // Solvers add what they hold to memory_bytes themselves.
  report.add_count("memory_bytes", held_bytes());
  if (kept) {
    auto precomputed = std::make_shared<JobPrecomputation>();
    precomputed->method = method_;
    precomputed->settings = settings_;
    precomputed->scene = scene_;
    precomputed->tracer = tracer_;
    precomputed->solver = std::move(kept);
    std::lock_guard lock(mutex_);
    precomputed_ = std::move(precomputed);
  }
  return std::move(run.field);
}

std::unique_ptr<IndirectField> BakeJob::solve_relight(Report& report) {
  context_.set_stage("validating", 0.0, 0.02);
  auto stage_start = std::chrono::steady_clock::now();
  const Scene& previous_scene = *previous_->scene;
  const SceneDescription& before = previous_scene.description;
  // A relight of the scene the previous bake copied (only its lights changed since) shares
  // its mesh storage: the check below then compares pointers, not every vertex.
  const bool shared_geometry = description_.meshes.shares_storage_with(before.meshes);
  report.set_number("relight_shared_geometry", shared_geometry ? 1.0 : 0.0);
  if (description_.meshes != before.meshes || description_.materials != before.materials ||
      description_.textures != before.textures) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "relight: the scene's geometry or materials differ from the bake it relights "
                "(only lights and the world may change); start a full bake");
  }
  // Same meshes and materials make the same triangles, so the previous BVH serves this scene,
  // and the previous scene's triangles and topology are reused rather than rebuilt (on
  // Sponza, rebuilding took seconds; a relight takes milliseconds).
  scene_ = std::make_shared<const Scene>(build_relit_scene(previous_scene, description_));
  const Scene& scene = *scene_;
  report.add_count("triangles", scene.triangles.size());
  report.add_count("lights", scene.description.lights.size());
  if (!scene.description.portals.empty()) {
    report.add_count("portals", scene.description.portals.size());
  }
  report.add_count("emissive_triangles", scene.emissive_triangles.size());
  report.add_seconds("validate", seconds_since(stage_start));
  context_.throw_if_cancelled();

  context_.set_stage("relighting", 0.1, 0.6);
  stage_start = std::chrono::steady_clock::now();
  tracer_ = previous_->tracer;
  const RayTracer& tracer = *tracer_;
  direct_ = std::make_unique<const DirectLight>(scene, tracer);
  const SolveInputs inputs{scene, tracer, *direct_, settings_, &points_, solver_memory()};
  std::unique_ptr<IndirectField> field;
  {
    const ProgressRange relighting(context_, 0.1, 0.6);  // the solver counts from 0 to 1 in it
    field = relight_solver(*solver_, inputs, previous_->solver, context_);
  }
  report.add_seconds("solve", seconds_since(stage_start));
  report.add_count("memory_bytes", held_bytes());
  return field;
}

MemoryBudget BakeJob::solver_memory() const {
  MemoryBudget budget(memory_budget_bytes_);
  budget.hold(held_bytes());
  return budget;
}

size_t BakeJob::held_bytes() const {
  return tracer_->memory_bytes() + description_bytes(description_) +
         scene_->triangles.capacity() * sizeof(Triangle) +
         scene_->shading.capacity() * sizeof(TriangleShading) +
         points_.size() * (kBytesPerPoint + kBytesPerResult);
}

bool BakeJob::wants_error_estimate() const {
  return !previous_ && method_ != "direct" && error_probes_ > 0 && !points_.positions.empty() &&
         direct_ != nullptr;
}

void BakeJob::estimate_error(Report& report) {
  context_.set_stage("estimating the error", context_.progress(), 1.0);
  const auto start = std::chrono::steady_clock::now();
  ErrorEstimateSettings settings;
  settings.samples = error_probe_samples_;
  settings.seed = uint64_t(SettingReader(settings_, method_schema(method_)).get_int("seed"));
  const ErrorProbes at_points =
      probes_weighted_by_light(points_, results_, size_t(error_probes_), settings.seed);
  const ErrorEstimate estimate =
      bakegi::estimate_error(*direct_, at_points, display_probes_, results_, settings, context_);
  report_error_estimate(estimate, report, start);
}

void BakeJob::report_error_estimate(const ErrorEstimate& estimate, Report& report,
                                    std::chrono::steady_clock::time_point start) {
  report.set_json("error_estimate", error_estimate_json(estimate));
  report.set_number("estimated_error", estimate.at_points.nrmse);
  std::string interval = "[";
  interval += json_number(estimate.at_points.low);
  interval += ", ";
  interval += json_number(estimate.at_points.high);
  interval += "]";
  report.set_json("estimated_error_interval", interval);
  report.add_count("error_probe_rays", estimate.rays);
  report.add_seconds("error_estimate", seconds_since(start));
}

void BakeJob::finish(bakegi_status status, std::string message) noexcept {
  const auto cancelled_in_time = [&] {
    if (status == BAKEGI_OK && context_.is_cancelled()) {
      status = BAKEGI_ERROR_CANCELLED;
      try {
        message = "the bake was cancelled";
      } catch (...) {
      }
    }
  };
  cancelled_in_time();
  // The field has been evaluated (or never will be); a relight keeps its own references.
  direct_.reset();
  tracer_.reset();
  scene_.reset();
  try {
    Report& report = context_.report();
    std::string settings = "{";
    for (const auto& [key, value] : settings_.used_values()) {
      if (settings.size() > 1) settings += ", ";
      settings += json_quote(key) + ": " + setting_to_json(value);
    }
    report.set_json("settings", settings + "}");
    report.set_text("status", bakegi_status_string(status));
    report.set_text("error", message);
    // Keys every report has, also when the job failed early.
    for (const char* key : {"triangles", "lights", "memory_bytes"}) report.add_count(key, 0);
    for (const char* stage : {"validate", "bvh", "solve", "evaluate", "total"}) {
      report.add_seconds(stage, 0.0);
    }
    if (status == BAKEGI_OK) {
      context_.set_stage("done", 1.0, 1.0);
    } else {
      context_.set_stage_text(status == BAKEGI_ERROR_CANCELLED ? "cancelled" : "failed");
    }
  } catch (...) {
    // The report is incomplete; status and message below still reach the caller.
  }
  std::lock_guard lock(mutex_);
  // cancel() sets the flag under this lock: checked again, no cancel slips in before done_.
  cancelled_in_time();
  status_ = status;
  try {
    error_ = message;
  } catch (...) {
  }
  done_ = true;
  done_changed_.notify_all();
}

}  // namespace bakegi
