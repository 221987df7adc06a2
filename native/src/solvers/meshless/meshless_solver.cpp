#include "solvers/meshless/meshless_solver.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <sstream>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "settings/settings.h"
#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/meshless_precomputation.h"
#include "solvers/meshless/multi_bounce.h"
#include "solvers/meshless/multilevel_approximation.h"
#include "solvers/meshless/point_placement.h"
#include "solvers/meshless/precomputation_cache.h"
#include "solvers/meshless/sky_visibility.h"
#include "solvers/meshless/transfer_refinement.h"
#include "solvers/meshless/visible_basis.h"
#include "solvers/meshless/visible_evaluation.h"
#include "solvers/precomputation_codec.h"
#include "util/bit_cast.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/report.h"

namespace bakegi {

using namespace meshless;

namespace {

// Where the world is an image its light at the senders is sampled (see light()): this many
// times the direct_samples setting.
constexpr int64_t kWorldImageDirectSampleFactor = 16;

struct MeshlessSettings {
  int64_t levels = 0;
  double coarse_spacing = 0.0;
  int64_t sender_levels = 0;
  double epsilon = 0.01;
  int64_t gather_rays = 256;
  int64_t bounces = 16;
  int64_t direct_samples = 4;  // times kWorldImageDirectSampleFactor with a world image
  double sender_cutoff = 1e-3;
  bool visibility = true;
  bool has_viewpoint = false;
  glm::vec3 viewpoint{0.0f};
  int64_t seed = 0;
  std::string cache_dir;  // empty: no precomputation cache

  static MeshlessSettings from(const Settings& given) {
    const SettingReader settings(given, method_schema("meshless"));
    MeshlessSettings s;
    s.levels = settings.get_int("levels");
    s.coarse_spacing = settings.get_float("coarse_spacing");
    s.sender_levels = settings.get_int("sender_levels");
    s.epsilon = settings.get_float("epsilon");
    s.gather_rays = settings.get_int("gather_rays");
    s.bounces = settings.get_int("bounces");
    s.direct_samples = settings.get_int("direct_samples");
    s.sender_cutoff = settings.get_float("sender_cutoff");
    s.visibility = settings.get_int("visibility") != 0;
    s.seed = settings.get_int("seed");
    s.cache_dir = settings.get_string("cache_dir");
    const std::string viewpoint = settings.get_string("viewpoint");
    if (!viewpoint.empty()) {
      std::istringstream in(viewpoint);
      char comma1 = 0, comma2 = 0;
      glm::vec3 v;
      if (!(in >> v.x >> comma1 >> v.y >> comma2 >> v.z) || comma1 != ',' || comma2 != ',' ||
          !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "setting 'viewpoint' must be three numbers \"x,y,z\", got '" + viewpoint + "'");
      }
      if (!position_in_range(v)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "setting 'viewpoint': " + position_out_of_range_text(v));
      }
      s.has_viewpoint = true;
      s.viewpoint = v;
    }
    return s;
  }
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <typename T>
std::string json_array(const std::vector<T>& values) {
  std::string json = "[";
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) json += ", ";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", double(values[i]));
    json += buffer;
  }
  return json + "]";
}

// What a bake reports about the precomputation, the same whether it was just made or loaded
// from the cache. Rays and stage times are the caller's: a load casts none.
void report_statistics(const MeshlessPrecomputation& system, Report& report) {
  const MeshlessStatistics& s = system.statistics;
  if (s.levels_reduced) {
    report.warn("meshless: the memory budget allows only " +
                std::to_string(system.all.level_count()) +
                " levels of basis functions, fewer than the automatic choice (coarser indirect "
                "light); raise memory_budget_mb");
  }
  if (s.refinement_stopped_at_level >= 0) {
    report.warn("meshless: the memory budget stopped link refinement before receiver level " +
                std::to_string(s.refinement_stopped_at_level) +
                " (coarser indirect light there); raise memory_budget_mb or epsilon");
  }
  std::vector<uint64_t> per_level;
  for (uint32_t l = 0; l < system.all.level_count(); ++l) {
    per_level.push_back(system.all.level_end(l) - system.all.level_begin(l));
  }
  report.set_json("meshless_points_per_level", json_array(per_level));
  report.add_count("meshless_points", system.all.size());
  report.add_count("meshless_sender_points", system.senders.size());
  report.add_count("meshless_sender_levels", s.sender_levels);
  report.set_json("meshless_receivers_per_level", json_array(s.receivers_per_level));
  report.set_json("meshless_links_per_level", json_array(s.links_per_level));
  report.add_count("meshless_links", s.links);
  report.add_count("meshless_potential_links", s.potential_links);
  report.set_number(
      "meshless_links_kept_percent",
      s.potential_links > 0 ? 100.0 * double(s.links) / double(s.potential_links) : 0.0);
  report.add_count("meshless_operator_entries", system.transfer.nonzeros());
  report.add_count("meshless_bounces", s.bounces);
  report.set_json("meshless_bounce_fractions", json_array(s.bounce_fractions));
  report.set_number("meshless_coarse_spacing", s.coarse_spacing);
  report.set_number("meshless_mean_free_path", s.mean_free_path);
  report.add_count("meshless_link_bytes", s.link_bytes);
  report.add_count("meshless_precomputation_bytes", system.memory_bytes());
}

}  // namespace

namespace {

// Identifies a set of bake points (positions and normals, bit for bit) and the rule.
uint64_t points_key(const BakePoints& points, bool visibility) {
  uint64_t key = mix64(points.size() * 2 + (visibility ? 1 : 0));
  auto add = [&key](const glm::vec3& v) {
    for (int a = 0; a < 3; ++a) key = mix64(key ^ bakegi::bit_cast<uint32_t>(v[a]));
  };
  for (size_t i = 0; i < points.size(); ++i) {
    add(points.positions[i]);
    add(points.normals[i]);
  }
  return key;
}

}  // namespace

void MeshlessField::evaluate(const BakePoints& points, std::span<glm::vec3> out,
                             JobContext& context) const {
  if (out.size() < points.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless: output smaller than the points");
  }
  if (points.size() == 0) return;
  std::vector<float> vectors(points.size() * 9);
  const auto start = std::chrono::steady_clock::now();
  const uint64_t key = points_key(points, visibility_ != nullptr);
  std::shared_ptr<const EvaluationWeights> weights = system_->weights_for(key);
  context.report().add_count("meshless_evaluation_weights_reused", weights ? 1 : 0);
  if (!weights) {
    auto computed = std::make_shared<EvaluationWeights>();
    const VisibleEvaluationStats stats =
        visible_weights(system_->all, visibility_, points.positions, points.normals, *computed,
                        &context, visibility_ ? system_->receiver_relations.get() : nullptr);
    context.report().add_count("rays", stats.rays);
    context.report().add_count("meshless_visibility_rays", stats.rays);
    context.report().add_count("meshless_visibility_blocked", stats.blocked);
    context.report().add_count("meshless_visibility_skipped_levels", stats.levels_skipped);
    context.report().add_count("meshless_visibility_blind_points", stats.points_blind);
    context.report().add_count("meshless_completed_levels", stats.levels_completed);
    context.report().add_count("meshless_uncovered_points", stats.uncovered);
    system_->keep_weights(key, computed);
    weights = std::move(computed);
  }
  weights->apply(irradiance_, 9, vectors);
  context.throw_if_cancelled();
  context.report().add_seconds("meshless_evaluation", seconds_since(start));
  for (size_t p = 0; p < points.size(); ++p) {
    const glm::vec3& n = points.normals[p];
    for (int c = 0; c < 3; ++c) {
      const float* v = &vectors[9 * p + 3 * c];
      // E = n · E_vector; the output convention is E_indirect / π, never negative.
      const float irradiance = n.x * v[0] + n.y * v[1] + n.z * v[2];
      out[p][c] =
          std::isfinite(irradiance) ? std::max(irradiance, 0.0f) / std::numbers::pi_v<float> : 0.0f;
    }
  }
}

// The meshless precomputation in the job's cache (bake/precomputation_store.h): files
// "meshless-<key>.bgcache" with magic 'M', as before the store existed.
class MeshlessCacheCodec : public PrecomputationCodec {
 public:
  std::string name() const override { return "meshless"; }
  char magic() const override { return 'M'; }
  uint32_t version() const override { return meshless::kPrecomputationCacheVersion; }
  // A viewpoint places the basis; without one the bake points do.
  bool keyed_by_points(const Settings& settings) const override {
    return !MeshlessSettings::from(settings).has_viewpoint;
  }
  void encode(const Precomputation& precomputation, ByteWriter& payload) const override {
    meshless::encode_precomputation(dynamic_cast<const MeshlessPrecomputation&>(precomputation),
                                    payload);
  }
  std::shared_ptr<const Precomputation> decode(ByteReader& payload,
                                               const JobContext* job) const override {
    return meshless::decode_precomputation(payload, job);
  }
  void report_loaded(const Precomputation& precomputation, Report& report) const override {
    const auto& loaded = dynamic_cast<const MeshlessPrecomputation&>(precomputation);
    report.set_number("meshless_cache_precompute_seconds", loaded.statistics.precompute_seconds);
    report.add_count("meshless_refinement_rays", 0);
    report_statistics(loaded, report);
  }
};

void MeshlessSolver::check_settings(const Settings& settings) const {
  (void)MeshlessSettings::from(settings);
}

const PrecomputationCodec* MeshlessSolver::codec() const {
  static const MeshlessCacheCodec codec;
  return &codec;
}

std::shared_ptr<const Precomputation> MeshlessSolver::precompute(const SolveInputs& inputs,
                                                                 JobContext& context) {
  const MeshlessSettings settings = MeshlessSettings::from(inputs.settings);
  Report& report = context.report();
  const Scene& scene = inputs.scene;
  const auto precompute_start = std::chrono::steady_clock::now();

  // §2.3: points.
  context.set_stage("meshless: placing points", 0.02, 0.15);
  auto start = std::chrono::steady_clock::now();
  PlacementSettings placement;
  placement.coarse_spacing = float(settings.coarse_spacing);
  placement.levels = uint32_t(settings.levels);
  placement.seed = uint64_t(settings.seed);
  // A point costs its DAG, R-tree entry and links; 1 KiB each leaves room for all of them.
  placement.max_points = std::max<uint64_t>(1000, inputs.memory.total() / 4 / 1024);
  PlacementStatistics placement_stats;
  std::vector<BasisPoint> points;
  if (settings.has_viewpoint) {
    points = place_points(scene, inputs.tracer, settings.viewpoint, placement, context,
                          &placement_stats);
  } else {
    if (inputs.points == nullptr || inputs.points->size() == 0) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "meshless: no bake points and no 'viewpoint' setting to place the basis from");
    }
    points =
        place_points(scene, inputs.tracer, *inputs.points, placement, context, &placement_stats);
  }
  report.add_seconds("meshless_placement", seconds_since(start));
  context.throw_if_cancelled();

  // §2.1-2.2: the basis and its sender part.
  context.set_stage("meshless: building the basis", 0.15, 0.2);
  start = std::chrono::steady_clock::now();
  BasisHierarchy all(points);
  const uint32_t levels = all.level_count();
  const uint32_t sender_levels = settings.sender_levels > 0
                                     ? std::min<uint32_t>(uint32_t(settings.sender_levels), levels)
                                     : std::max<uint32_t>(1, levels - 1);
  std::vector<BasisPoint> sender_points;
  for (uint32_t i = 0; i < all.level_end(sender_levels - 1); ++i) {
    sender_points.push_back(all.point(i));
  }
  auto system = std::make_shared<MeshlessPrecomputation>(std::move(all),
                                                         BasisHierarchy(std::move(sender_points)));
  report.add_seconds("meshless_basis", seconds_since(start));
  context.throw_if_cancelled();

  // §3.2: the single-bounce operator by adaptive refinement.
  context.set_stage("meshless: refining links", 0.2, 0.85);
  start = std::chrono::steady_clock::now();
  RefinementSettings refinement;
  refinement.epsilon = float(settings.epsilon);
  refinement.gather.rays = uint32_t(settings.gather_rays);
  refinement.gather.seed = uint64_t(settings.seed) ^ 0x7472616e73666572ull;
  refinement.gather.ray_epsilon = inputs.direct.ray_epsilon();
  refinement.gather.visibility = settings.visibility;
  const std::vector<glm::vec3> folded_glossy = glossy_as_diffuse(scene);
  refinement.gather.glossy_as_diffuse = &folded_glossy;
  // Half of what the job's holdings and the basis leave (the other half: S and its caches).
  const uint64_t left = inputs.memory.remaining_after(system->memory_bytes());
  refinement.link_budget_bytes = left > 0 ? left / 2 : 1;
  RefinementStats refinement_stats;
  auto receiver_relations = settings.visibility ? std::make_shared<VisibleRelations>() : nullptr;
  const TransferOperator single =
      refine_transfer(scene, inputs.tracer, system->all, system->senders, refinement, context,
                      refinement_stats, receiver_relations.get());
  system->receiver_relations = std::move(receiver_relations);
  report.add_count("meshless_gather_hits_completed", refinement_stats.hits_completed);
  const double refine_seconds = seconds_since(start);
  report.add_seconds("meshless_refinement", refine_seconds);

  // The world's share of the senders' direct light, from geometry (sky_visibility.h).
  context.set_stage("meshless: sky visibility", 0.85, 0.87);
  start = std::chrono::steady_clock::now();
  SkyVisibilitySettings sky;
  sky.ray_epsilon = inputs.direct.ray_epsilon();
  sky.seed = uint64_t(settings.seed) ^ 0x736b79ull;
  uint64_t sky_rays = 0;
  system->sender_sky_visibility =
      sky_visibility(system->senders, inputs.tracer, sky, context, sky_rays);
  report.add_seconds("meshless_sky_visibility", seconds_since(start));

  // §3.1: S = T + T² + … on the coarsest receivers.
  context.set_stage("meshless: bounces", 0.87, 0.95);
  start = std::chrono::steady_clock::now();
  BounceSettings bounces;
  bounces.max_bounces = uint32_t(settings.bounces);
  bounces.truncation = float(settings.epsilon) * 1e-3f;
  BounceStats bounce_stats;
  system->transfer = solve_bounces(system->all, single, bounces, context, bounce_stats);
  report.add_seconds("meshless_bounces", seconds_since(start));

  // Statistics, kept with the precomputation for cache hits.
  MeshlessStatistics& statistics = system->statistics;
  statistics.sender_levels = sender_levels;
  statistics.receivers_per_level = refinement_stats.receivers_per_level;
  statistics.links_per_level = refinement_stats.links_per_level;
  statistics.links = refinement_stats.links;
  statistics.potential_links = refinement_stats.potential_links;
  statistics.refinement_stopped_at_level = refinement_stats.stopped_at_level;
  statistics.levels_reduced = placement_stats.levels_reduced;
  statistics.bounces = bounce_stats.bounces;
  statistics.bounce_fractions = bounce_stats.bounce_fraction;
  statistics.coarse_spacing =
      placement_stats.levels.empty() ? 0.0 : placement_stats.levels[0].spacing;
  statistics.mean_free_path = placement_stats.mean_free_path;
  statistics.link_bytes = single.memory_bytes();
  statistics.placement_rays = placement_stats.particle_rays + placement_stats.harmonic_mean_rays;
  statistics.refinement_rays = refinement_stats.rays + sky_rays;
  statistics.precompute_seconds = seconds_since(precompute_start);
  report.add_count("rays", statistics.placement_rays + statistics.refinement_rays);
  report.add_count("meshless_refinement_rays", statistics.refinement_rays);
  report_statistics(*system, report);
  return system;
}

std::unique_ptr<IndirectField> MeshlessSolver::light(
    const SolveInputs& inputs, std::shared_ptr<const Precomputation> precomputation,
    JobContext& context) {
  // The field keeps the precomputation alive for as long as it is evaluated.
  std::shared_ptr<const MeshlessPrecomputation> system =
      std::dynamic_pointer_cast<const MeshlessPrecomputation>(precomputation);
  if (!system) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless: the precomputation to light was made by another method");
  }
  const MeshlessSettings settings = MeshlessSettings::from(inputs.settings);
  Report& report = context.report();

  // §3.3: direct irradiance at the sender points, projected with P†. The lamps and emitters
  // are sampled; a constant world is π L V from the stored sky visibility (sky_visibility.h),
  // a world image is sampled with the lamps (its light depends on where the sky is seen).
  context.set_stage("meshless: direct light", 0.95, 0.98);
  auto start = std::chrono::steady_clock::now();
  const BasisHierarchy& senders = system->senders;
  if (system->sender_sky_visibility.size() != senders.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "meshless: sky visibility and senders disagree");
  }
  const bool world_image = inputs.direct.has_environment();
  const glm::dvec3 world_irradiance =
      world_image ? glm::dvec3(0.0) : std::numbers::pi * glm::dvec3(inputs.direct.world_radiance());
  const DirectLight::World sampled_world =
      world_image ? DirectLight::World::kIncluded : DirectLight::World::kExcluded;
  // Sampled rather than read from the stored visibility, a sky seen through a small opening
  // is noisy at the few samples lamps need (test_solver_light_types, 4 samples: a face 16%
  // off; 64: within 5%).
  const int64_t direct_samples =
      settings.direct_samples * (world_image ? kWorldImageDirectSampleFactor : 1);
  std::vector<float> direct(senders.size() * 3, 0.0f);
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, senders.size(), 64),
      [&](const tbb::blocked_range<size_t>& range) {
        if (context.is_cancelled()) return;
        uint64_t local_rays = 0;
        for (size_t j = range.begin(); j != range.end(); ++j) {
          const BasisPoint& p = senders.point(uint32_t(j));
          const SurfacePoint x{p.position, p.normal, p.normal};
          glm::dvec3 sum(0.0);
          for (int64_t s = 0; s < direct_samples; ++s) {
            RandomStream rng = sample_stream(uint64_t(settings.seed), j, uint64_t(s));
            sum += glm::dvec3(inputs.direct.irradiance_sample(x, rng, local_rays, sampled_world));
          }
          const glm::dvec3 mean = sum / double(direct_samples) +
                                  world_irradiance * double(system->sender_sky_visibility[j]);
          for (int c = 0; c < 3; ++c) direct[3 * j + c] = float(mean[c]);
        }
        rays += local_rays;
      });
  context.throw_if_cancelled();
  const double direct_seconds = seconds_since(start);
  start = std::chrono::steady_clock::now();
  const std::shared_ptr<const VisibleRelations> relations =
      system->sender_relations(settings.visibility ? &inputs.tracer : nullptr, &context);
  const std::vector<float> e = visible_pull_push_project(senders, *relations, direct, 3, &context);
  const double projection_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  std::vector<float> indirect;
  // §3.3: "skipping senders below ε": coefficients this small next to the largest add
  // nothing visible, and under a spot light most of them are.
  float largest = 0.0f;
  for (float value : e) largest = std::max(largest, std::abs(value));
  apply_operator(system->transfer, system->all, uint32_t(settings.bounces),
                 BounceSettings{}.tolerance, e, float(settings.sender_cutoff) * largest, indirect);
  const double apply_seconds = seconds_since(start);

  report.add_count("rays", rays.load());
  report.add_seconds("meshless_direct", direct_seconds);
  report.add_seconds("meshless_projection", projection_seconds);
  report.add_seconds("meshless_apply", apply_seconds);
  report.add_count("memory_bytes", system->memory_bytes() + indirect.size() * sizeof(float));
  return std::make_unique<MeshlessField>(std::move(system), std::move(indirect),
                                         settings.visibility ? &inputs.tracer : nullptr);
}

}  // namespace bakegi
