#include "solvers/meshless/meshless_solver.h"

#include <algorithm>
#include <atomic>
#include <bit>
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

#include "direct/direct_light.h"
#include "direct/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/multi_bounce.h"
#include "solvers/meshless/multilevel_approximation.h"
#include "solvers/meshless/point_placement.h"
#include "solvers/meshless/transfer_refinement.h"
#include "solvers/meshless/visible_evaluation.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/report.h"
#include "util/settings.h"

namespace bakegi {

using namespace meshless;

namespace {

struct MeshlessSettings {
  int64_t levels = 0;
  double coarse_spacing = 0.0;
  int64_t sender_levels = 0;
  double epsilon = 0.01;
  int64_t gather_rays = 256;
  int64_t bounces = 16;
  int64_t direct_samples = 16;
  bool visibility = true;
  bool has_viewpoint = false;
  glm::vec3 viewpoint{0.0f};
  int64_t seed = 0;
  uint64_t memory_budget_bytes = uint64_t(4096) << 20;

  static MeshlessSettings from(const Settings& settings) {
    MeshlessSettings s;
    s.levels = settings.get_int("levels", 0, 0, 12);
    s.coarse_spacing = settings.get_float("coarse_spacing", 0.0, 0.0, 1e9);
    s.sender_levels = settings.get_int("sender_levels", 0, 0, 12);
    s.epsilon = settings.get_float("epsilon", 0.01, 0.0, 10.0);
    s.gather_rays = settings.get_int("gather_rays", 256, 1, 65536);
    s.bounces = settings.get_int("bounces", 16, 1, 1000);
    s.direct_samples = settings.get_int("direct_samples", 16, 1, 65536);
    s.visibility = settings.get_int("visibility", 1, 0, 1) != 0;
    s.seed = settings.get_int("seed", 0, 0, std::numeric_limits<int64_t>::max());
    s.memory_budget_bytes =
        uint64_t(settings.get_int("memory_budget_mb", 4096, 1, int64_t(1) << 30)) << 20;
    const std::string viewpoint = settings.get_string("viewpoint", "");
    if (!viewpoint.empty()) {
      std::istringstream in(viewpoint);
      char comma1 = 0, comma2 = 0;
      glm::vec3 v;
      if (!(in >> v.x >> comma1 >> v.y >> comma2 >> v.z) || comma1 != ',' || comma2 != ',' ||
          !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "setting 'viewpoint' must be three numbers \"x,y,z\", got '" + viewpoint + "'");
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

}  // namespace

// What relighting reuses: the basis, the sender basis and S (geometry, materials, settings).
struct MeshlessPrecomputation : Precomputation,
                                std::enable_shared_from_this<MeshlessPrecomputation> {
  explicit MeshlessPrecomputation(BasisHierarchy all_in, BasisHierarchy senders_in)
      : all(std::move(all_in)), senders(std::move(senders_in)) {}
  BasisHierarchy all;      // every receiver level
  BasisHierarchy senders;  // the first sender levels of the same points (same indices)
  DirectToIndirect transfer;

  // The evaluation weights of the last bake points evaluated, so that relighting the same
  // points is one sparse product (no R-tree queries, no visibility rays). Keyed by a hash of
  // the points and the visibility flag.
  std::shared_ptr<const EvaluationWeights> weights_for(uint64_t key) const {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    return key == weights_key_ ? weights_ : nullptr;
  }
  void keep_weights(uint64_t key, std::shared_ptr<const EvaluationWeights> weights) const {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    weights_key_ = key;
    weights_ = std::move(weights);
  }

  size_t memory_bytes() const override {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    return all.memory_bytes() + senders.memory_bytes() + transfer.memory_bytes() +
           (weights_ ? weights_->memory_bytes() : 0);
  }

 private:
  mutable std::mutex weights_mutex_;
  mutable std::shared_ptr<const EvaluationWeights> weights_;
  mutable uint64_t weights_key_ = 0;
};

namespace {

// Identifies a set of bake points (positions and normals, bit for bit) and the rule.
uint64_t points_key(const BakePoints& points, bool visibility) {
  uint64_t key = mix64(points.size() * 2 + (visibility ? 1 : 0));
  auto add = [&key](const glm::vec3& v) {
    for (int a = 0; a < 3; ++a) key = mix64(key ^ std::bit_cast<uint32_t>(v[a]));
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
    const VisibleEvaluationStats stats = visible_weights(
        system_->all, visibility_, points.positions, points.normals, *computed, &context);
    context.report().add_count("rays", stats.rays);
    context.report().add_count("meshless_visibility_rays", stats.rays);
    context.report().add_count("meshless_visibility_blocked", stats.blocked);
    context.report().add_count("meshless_visibility_skipped_levels", stats.levels_skipped);
    context.report().add_count("meshless_visibility_unblocked_points", stats.points_unblocked);
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

std::unique_ptr<IndirectField> MeshlessSolver::solve(const SolveInputs& inputs,
                                                     JobContext& context) {
  precomputation_.reset();
  (void)MeshlessSettings::from(inputs.settings);  // bad settings fail before any work
  std::shared_ptr<const MeshlessPrecomputation> system = precompute(inputs, context);
  std::unique_ptr<IndirectField> field = light(inputs, system, context);
  precomputation_ = std::move(system);
  return field;
}

std::unique_ptr<IndirectField> MeshlessSolver::relight(const SolveInputs& inputs,
                                                       const Precomputation& reuse,
                                                       JobContext& context) {
  const auto* system = dynamic_cast<const MeshlessPrecomputation*>(&reuse);
  if (!system) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless: the precomputation to relight from was made by another method");
  }
  context.report().set_number("meshless_relit", 1.0);
  // The field keeps the precomputation alive for as long as it is evaluated.
  std::shared_ptr<const MeshlessPrecomputation> shared = system->shared_from_this();
  return light(inputs, shared, context);
}

std::shared_ptr<const MeshlessPrecomputation> MeshlessSolver::precompute(
    const SolveInputs& inputs, JobContext& context) const {
  const MeshlessSettings settings = MeshlessSettings::from(inputs.settings);
  Report& report = context.report();
  const Scene& scene = inputs.scene;

  // §2.3: points.
  context.set_stage("meshless: placing points", 0.02, 0.15);
  auto start = std::chrono::steady_clock::now();
  PlacementSettings placement;
  placement.coarse_spacing = float(settings.coarse_spacing);
  placement.levels = uint32_t(settings.levels);
  placement.seed = uint64_t(settings.seed);
  // A point costs its DAG, R-tree entry and links; 1 KiB each leaves room for all of them.
  placement.max_points = std::max<uint64_t>(1000, settings.memory_budget_bytes / 4 / 1024);
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
                                     : (levels + 1) / 2;
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
  const size_t used = system->memory_bytes() + inputs.tracer.memory_bytes();
  refinement.link_budget_bytes =
      settings.memory_budget_bytes > used ? (settings.memory_budget_bytes - used) / 2 : 1;
  RefinementStats refinement_stats;
  const TransferOperator single = refine_transfer(
      scene, inputs.tracer, system->all, system->senders, refinement, context, refinement_stats);
  const double refine_seconds = seconds_since(start);
  report.add_seconds("meshless_refinement", refine_seconds);
  if (refinement_stats.stopped_at_level >= 0) {
    report.warn("meshless: the memory budget stopped link refinement before receiver level " +
                std::to_string(refinement_stats.stopped_at_level) +
                " (coarser indirect light there); raise memory_budget_mb or epsilon");
  }

  // §3.1: S = T + T² + … on the coarsest receivers.
  context.set_stage("meshless: bounces", 0.85, 0.95);
  start = std::chrono::steady_clock::now();
  BounceSettings bounces;
  bounces.max_bounces = uint32_t(settings.bounces);
  bounces.truncation = float(settings.epsilon) * 1e-3f;
  BounceStats bounce_stats;
  system->transfer = solve_bounces(system->all, single, bounces, context, bounce_stats);
  report.add_seconds("meshless_bounces", seconds_since(start));

  // Statistics (issue 4, item 7).
  std::vector<uint64_t> per_level;
  for (uint32_t l = 0; l < levels; ++l) {
    per_level.push_back(system->all.level_end(l) - system->all.level_begin(l));
  }
  report.set_json("meshless_points_per_level", json_array(per_level));
  report.add_count("meshless_points", system->all.size());
  report.add_count("meshless_sender_points", system->senders.size());
  report.add_count("meshless_sender_levels", sender_levels);
  report.set_json("meshless_receivers_per_level", json_array(refinement_stats.receivers_per_level));
  report.set_json("meshless_links_per_level", json_array(refinement_stats.links_per_level));
  report.add_count("meshless_links", refinement_stats.links);
  report.add_count("meshless_potential_links", refinement_stats.potential_links);
  report.set_number(
      "meshless_links_kept_percent",
      refinement_stats.potential_links > 0
          ? 100.0 * double(refinement_stats.links) / double(refinement_stats.potential_links)
          : 0.0);
  report.add_count("meshless_operator_entries", bounce_stats.nonzeros);
  report.add_count("meshless_bounces", bounce_stats.bounces);
  report.set_json("meshless_bounce_fractions", json_array(bounce_stats.bounce_fraction));
  report.add_count("rays", refinement_stats.rays + placement_stats.particle_rays +
                               placement_stats.harmonic_mean_rays);
  report.add_count("meshless_refinement_rays", refinement_stats.rays);
  report.set_number("meshless_coarse_spacing",
                    placement_stats.levels.empty() ? 0.0 : placement_stats.levels[0].spacing);
  report.add_count("meshless_link_bytes", single.memory_bytes());
  report.add_count("meshless_precomputation_bytes", system->memory_bytes());
  return system;
}

std::unique_ptr<IndirectField> MeshlessSolver::light(
    const SolveInputs& inputs, std::shared_ptr<const MeshlessPrecomputation> system,
    JobContext& context) const {
  const MeshlessSettings settings = MeshlessSettings::from(inputs.settings);
  Report& report = context.report();

  // §3.3: direct irradiance at the sender points, projected with P†.
  context.set_stage("meshless: direct light", 0.95, 0.98);
  auto start = std::chrono::steady_clock::now();
  const BasisHierarchy& senders = system->senders;
  std::vector<float> direct(senders.size() * 3, 0.0f);
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, senders.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (context.is_cancelled()) return;
                      uint64_t local_rays = 0;
                      for (size_t j = range.begin(); j != range.end(); ++j) {
                        const BasisPoint& p = senders.point(uint32_t(j));
                        const SurfacePoint x{p.position, p.normal, p.normal};
                        glm::dvec3 sum(0.0);
                        for (int64_t s = 0; s < settings.direct_samples; ++s) {
                          Pcg32 rng = sample_stream(uint64_t(settings.seed), j, uint64_t(s));
                          sum += glm::dvec3(inputs.direct.irradiance_sample(x, rng, local_rays));
                        }
                        const glm::dvec3 mean = sum / double(settings.direct_samples);
                        for (int c = 0; c < 3; ++c) direct[3 * j + c] = float(mean[c]);
                      }
                      rays += local_rays;
                    });
  context.throw_if_cancelled();
  const std::vector<float> e = pull_push_project(senders, direct, 3, &context);
  const double direct_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  std::vector<float> indirect;
  apply_operator(system->transfer, e, 0.0f, indirect);
  const double apply_seconds = seconds_since(start);

  report.add_count("rays", rays.load());
  report.add_seconds("meshless_direct", direct_seconds);
  report.add_seconds("meshless_apply", apply_seconds);
  report.add_count("memory_bytes", system->memory_bytes() + indirect.size() * sizeof(float));
  return std::make_unique<MeshlessField>(std::move(system), std::move(indirect),
                                         settings.visibility ? &inputs.tracer : nullptr);
}

}  // namespace bakegi
