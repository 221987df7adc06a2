#include "solvers/antiradiance/antiradiance_solver.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "scene/ray_tracer.h"
#include "settings/settings.h"
#include "solvers/antiradiance/antiradiance_precomputation.h"
#include "solvers/antiradiance/back_sides.h"
#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/direct_initialization.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/global_pass.h"
#include "solvers/antiradiance/iteration.h"
#include "solvers/antiradiance/link_refinement.h"
#include "solvers/antiradiance/patch_radiance_cache.h"
#include "solvers/antiradiance/precomputation_cache.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "solvers/pathtrace/controlled_path_field.h"
#include "solvers/precomputation_codec.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/report.h"

namespace bakegi {
namespace {

using namespace antiradiance;

// A first guess of the links, only to choose the automatic patch size before linking (the
// real count is known only after refinement, which max_links bounds). The oracle refines
// until a sender covers one bin, so links grow with the bin count m. Measured: an inward
// icosphere (10k elements) keeps 47, 196 and 760 links per element at 48, 192 and 768 bins,
// a coarse Cornell box (31k elements, 192 bins) 147: about m per element.
constexpr uint64_t kEstimatedLinksPerElementPerBin = 1;
// Links live twice for a moment: the refinement's array and the receiver-grouped copy the
// global pass makes of it.
constexpr uint64_t kPeakBytesPerLink = 2 * sizeof(Link);
// The field keeps one interpolation sample per patch plus its grid (about 4 cells each).
constexpr uint64_t kFieldBytesPerPatch = sizeof(SurfaceSample) + sizeof(float) + 24;

// The automatic patch size keeps the hierarchy's estimate at most this large. The estimate
// counts a back side for every triangle of an open mesh, so it is an upper bound: the Cornell
// box at extent / 16 keeps its 3,260 triangles whole (6.5k elements); the office at 1.15 m
// has 17k.
constexpr uint64_t kAutomaticElementLimit = 65536;

// A solve whose iteration diverged and kept no more than this many iterations is unusable
// (CannotModel): the bake falls back to the path tracer.
constexpr size_t kUnusableIterations = 2;

struct AntiradianceSettings {
  int64_t bins = 300;
  int64_t iterations = 32;
  double tolerance = 1e-4;
  IterationScheme scheme = IterationScheme::kSymmetric;
  double patch_size = 0.0;
  int64_t direct_samples = 64;
  OracleExtent oracle = OracleExtent::kBoundingSphere;
  double oracle_factor = 1.0;
  double glossy_fold_exponent = 16.0;
  int64_t seed = 0;
  int64_t near_field_rays = 256;
  double near_field_distance = 0.5;
  bool residual_path_traced = false;
  double residual_fraction = 0.0;

  static AntiradianceSettings from(const Settings& given) {
    const SettingReader settings(given, method_schema("antiradiance"));
    AntiradianceSettings s;
    s.bins = settings.get_int("bins");
    s.iterations = settings.get_int("iterations");
    s.tolerance = settings.get_float("tolerance");
    const std::string scheme = settings.get_string("scheme");
    if (scheme == "symmetric") {
      s.scheme = IterationScheme::kSymmetric;
    } else if (scheme == "asymmetric") {
      s.scheme = IterationScheme::kAsymmetric;
    } else {
      throw Error(
          BAKEGI_ERROR_INVALID_ARGUMENT,
          "setting \"scheme\" must be \"symmetric\" or \"asymmetric\", not \"" + scheme + "\"");
    }
    s.patch_size = settings.get_float("patch_size");
    s.residual_path_traced = settings.get_string("residual") == "path_traced";
    s.residual_fraction = settings.get_float("residual_fraction");
    s.direct_samples = settings.get_int("direct_samples");
    const std::string oracle = settings.get_string("oracle");
    if (oracle == "sphere") {
      s.oracle = OracleExtent::kBoundingSphere;
    } else if (oracle == "projected") {
      s.oracle = OracleExtent::kProjectedArea;
    } else {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "setting \"oracle\" must be \"sphere\" or \"projected\", not \"" + oracle + "\"");
    }
    s.oracle_factor = settings.get_float("oracle_factor");
    s.glossy_fold_exponent = settings.get_float("glossy_fold_exponent");
    s.seed = settings.get_int("seed");
    s.near_field_rays = settings.get_int("near_field_rays");
    s.near_field_distance = settings.get_float("near_field_distance");
    return s;
  }
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string megabytes(uint64_t bytes) {
  return MemoryBudget::megabytes(bytes);
}

std::string metres(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.4g m", value);
  return text;
}

uint64_t saturating_add(uint64_t a, uint64_t b) {
  return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max()
                                                      : a + b;
}

uint64_t saturating_multiply(uint64_t a, uint64_t b) {
  return b != 0 && a > std::numeric_limits<uint64_t>::max() / b
             ? std::numeric_limits<uint64_t>::max()
             : a * b;
}

// Everything but the links, for patches of at most `max_edge`.
uint64_t bytes_without_links(const PatchCount& count, float max_edge, int bins) {
  const uint64_t elements = count.elements(max_edge);
  const uint64_t patches = count.patches(max_edge);
  uint64_t bytes = count.hierarchy_bytes(max_edge);
  bytes = saturating_add(bytes, RadianceTables::bytes(elements, patches, uint64_t(bins)));
  return saturating_add(bytes, saturating_multiply(patches, kFieldBytesPerPatch));
}

uint64_t estimated_bytes(const PatchCount& count, float max_edge, int bins) {
  const uint64_t links = saturating_multiply(count.elements(max_edge),
                                             kEstimatedLinksPerElementPerBin * uint64_t(bins));
  return saturating_add(bytes_without_links(count, max_edge, bins),
                        saturating_multiply(links, kPeakBytesPerLink));
}

// The smallest max_edge · 2^k (k ≥ 0) whose estimate fits `available`, or nullopt when even
// the coarsest patches do not fit.
std::optional<float> patch_size_within(const PatchCount& count, float max_edge, int bins,
                                       uint64_t available) {
  const uint64_t elements = std::max<uint64_t>(count.elements(max_edge), 1);
  const uint64_t bytes = estimated_bytes(count, max_edge, bins);
  const uint64_t per_element = std::max<uint64_t>(bytes / elements, 1);
  float edge =
      count.max_edge_within_budget(max_edge, std::max<uint64_t>(available / per_element, 1));
  // The per-element cost is an average; step on by doubling while the estimate is still over.
  for (int step = 0; step < 64 && estimated_bytes(count, edge, bins) > available; ++step) {
    const float next = edge * 2.0f;
    if (!std::isfinite(next) || count.elements(next) == count.elements(edge)) return std::nullopt;
    edge = next;
  }
  if (estimated_bytes(count, edge, bins) > available) return std::nullopt;
  return edge;
}

LinkingOptions linking_options(const AntiradianceSettings& settings, uint64_t max_links) {
  LinkingOptions options;
  options.max_links = max_links;
  options.extent = settings.oracle;
  options.oracle_factor = settings.oracle_factor;
  return options;
}

// The most Σ_patches a · luminance(E_acc) any solution can reach: each bounce reflects at most
// the largest reflectance ρ (diffuse + glossy, any channel) of what arrived, and in a closed
// scene at most all of it arrives again, so E_acc's flux is at most Φ_direct (ρ + ρ² + …) =
// Φ_direct ρ / (1 − ρ). Twice that leaves room for the discretization's own error; a
// solution beyond it is garbage (the iteration's divergence test). Infinite for ρ ≥ 1.
double flux_bound(const ElementHierarchy& hierarchy, std::span<const glm::vec3> direct) {
  double rho = 0.0, direct_flux = 0.0;
  for (size_t p = 0; p < hierarchy.patch_count(); ++p) {
    const Patch& patch = hierarchy.patches()[p];
    const glm::vec3 reflectance = patch.albedo + patch.glossy;
    rho = std::max({rho, double(reflectance.x), double(reflectance.y), double(reflectance.z)});
    const glm::vec3 e = direct[p];
    direct_flux += double(hierarchy.elements()[patch.element].area) * luminance(e);
  }
  if (rho >= 1.0 || !std::isfinite(direct_flux)) return std::numeric_limits<double>::infinity();
  return 2.0 * std::max(direct_flux, 0.0) * rho / (1.0 - rho);
}

std::string residual_history_json(const IterationResult& result) {
  std::string json = "[";
  for (const IterationRecord& record : result.history) {
    if (json.size() > 1) json += ", ";
    json += json_number(record.residual);
  }
  return json + "]";
}

// sqrt(2 · mean patch area): the edge of a typical patch (as the splat measures it).
float typical_patch_edge(const std::vector<SurfaceSample>& samples) {
  double area = 0.0;
  for (const SurfaceSample& s : samples) area += double(s.area);
  return samples.empty() ? 0.0f : float(std::sqrt(2.0 * area / double(samples.size())));
}

// A cached precomputation matched this scene's key, so only a forged file fails this; it keeps
// light() from indexing past the triangles (the locator, direct light) and from casting rays
// from outside the scene (the file's loader checked that everything lies within the root's
// bounds).
void check_made_for(const ElementHierarchy& hierarchy, const Scene& scene) {
  const size_t triangles = scene.triangles.size();
  bool fits = true;
  for (const Patch& patch : hierarchy.patches()) fits = fits && patch.triangle < triangles;
  for (const MemberTriangle& member : hierarchy.members_all()) {
    fits = fits && member.triangle < triangles;
  }
  // Room for the rounding of points interpolated on the triangles.
  const glm::vec3 far = glm::max(glm::abs(scene.bounds_min), glm::abs(scene.bounds_max));
  const glm::vec3 room(1e-3f * scene.extent() + 1e-5f * std::max({far.x, far.y, far.z}) + 1e-6f);
  const Element& root = hierarchy.root();
  fits = fits && glm::all(glm::greaterThanEqual(root.bounds_min, scene.bounds_min - room)) &&
         glm::all(glm::lessThanEqual(root.bounds_max, scene.bounds_max + room));
  if (!fits) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "antiradiance: the precomputation was made for another scene");
  }
}

// What the hierarchy, links and iteration came to, for the report (whatever the output).
void report_solution(Report& report, const AntiradiancePrecomputation& system,
                     const RadianceTables& tables, const IterationResult& result,
                     double direct_seconds, double iterate_seconds) {
  const ElementHierarchy& hierarchy = system.hierarchy;
  report.add_count("antiradiance_bins", uint64_t(system.bins.bin_count()));
  report.add_count("antiradiance_elements", hierarchy.element_count());
  report.add_count("antiradiance_patches", hierarchy.patch_count());
  report.add_count("antiradiance_back_side_patches", hierarchy.back_side_count());
  report.add_count("antiradiance_merged_patches", hierarchy.merged_patch_count());
  report.add_count("antiradiance_merged_triangles", hierarchy.member_count());
  report.add_count("antiradiance_links", system.link_statistics.link_count);
  report.add_count("antiradiance_iterations", result.history.size());
  report.add_count("antiradiance_table_bytes", tables.memory_bytes());
  report.add_count("antiradiance_link_bytes", system.transport.memory_bytes());
  report.add_count("antiradiance_hierarchy_bytes", hierarchy.memory_bytes());
  report.set_number("antiradiance_patch_size", double(hierarchy.max_edge()));
  report.set_text("antiradiance_scheme",
                  result.scheme_used == IterationScheme::kSymmetric ? "symmetric" : "asymmetric");
  report.set_json("antiradiance_residuals", residual_history_json(result));
  report.set_number("antiradiance_converged", result.converged ? 1.0 : 0.0);
  report.add_seconds("antiradiance_direct", direct_seconds);
  report.add_seconds("antiradiance_iterate", iterate_seconds);
}

}  // namespace

void AntiradianceField::evaluate(const BakePoints& points, std::span<glm::vec3> out,
                                 JobContext& context) const {
  if (out.size() < points.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "antiradiance: output smaller than the points");
  }
  constexpr size_t kBlock = 256;
  std::atomic<size_t> done{0};
  std::atomic<uint64_t> rays{0}, off_surface{0}, unanswered{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), kBlock),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (context.is_cancelled()) return;
                      uint64_t local_rays = 0;
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        // Per point: a near-field gather of many rays takes milliseconds.
                        if (context.is_cancelled()) return;
                        bool off = false;
                        const glm::vec3 splat =
                            interpolation_.evaluate(points.positions[i], points.normals[i], &off);
                        if (off) {
                          // In open space the patches say nothing: gather from the solution.
                          ++off_surface;
                          if (!near_field_.gather_off_surface(
                                  points.positions[i], points.normals[i], i, out[i], local_rays)) {
                            ++unanswered;
                            out[i] = splat;
                          }
                          continue;
                        }
                        out[i] = near_field_.evaluate(points.positions[i], points.normals[i], i,
                                                      splat, local_rays);
                      }
                      rays += local_rays;
                      const size_t finished = done.fetch_add(range.size()) + range.size();
                      context.set_stage_progress(double(finished) / double(points.size()));
                    });
  context.throw_if_cancelled();
  if (rays.load() > 0) context.report().add_count("rays", rays.load());
  context.report().add_count("antiradiance_off_surface_points", off_surface.load());
  if (unanswered.load() > 0) {
    context.report().warn(
        "antiradiance: " + std::to_string(unanswered.load()) +
        " bake points lie off every surface (beyond the interpolation's reach of any patch) "
        "and got the nearest patch's light, which is not theirs: set near_field_rays > 0 "
        "(they then gather from the solution) or put the points on surfaces");
  }
}

// The antiradiance precomputation in the job's cache (bake/precomputation_store.h): files
// "antiradiance-<key>.bgcache" with magic 'A', the payload in precomputation_cache.h.
class AntiradianceCacheCodec : public PrecomputationCodec {
 public:
  std::string name() const override { return "antiradiance"; }
  char magic() const override { return 'A'; }
  uint32_t version() const override { return antiradiance::kPrecomputationCacheVersion; }
  // Patches and links follow the geometry and the patch size only; bake points are used
  // nowhere before light() (the field is evaluated at whatever points it gets).
  bool keyed_by_points(const Settings&) const override { return false; }
  void encode(const Precomputation& precomputation, ByteWriter& payload) const override {
    antiradiance::encode_precomputation(
        dynamic_cast<const AntiradiancePrecomputation&>(precomputation), payload);
  }
  std::shared_ptr<const Precomputation> decode(ByteReader& payload,
                                               const JobContext* job) const override {
    return antiradiance::decode_precomputation(payload, job);
  }
  // light() reports the counts (elements, patches, links) from the precomputation, loaded or
  // not; what precompute() alone reports is its warnings and its seconds.
  void report_loaded(const Precomputation& precomputation, Report& report) const override {
    const auto& loaded = dynamic_cast<const AntiradiancePrecomputation&>(precomputation);
    for (const std::string& warning : loaded.warnings) report.warn(warning);
    report.set_number("antiradiance_cache_precompute_seconds", loaded.seconds);
  }
};

void AntiradianceSolver::check_settings(const Settings& settings) const {
  (void)AntiradianceSettings::from(settings);
}

const PrecomputationCodec* AntiradianceSolver::codec() const {
  static const AntiradianceCacheCodec codec;
  return &codec;
}

std::shared_ptr<const Precomputation> AntiradianceSolver::precompute(const SolveInputs& inputs,
                                                                     JobContext& context) {
  // Bad settings fail here, before any work.
  const AntiradianceSettings settings = AntiradianceSettings::from(inputs.settings);
  const Scene& scene = inputs.scene;
  Report& report = context.report();

  context.set_stage("antiradiance: bins", 0.0, 0.02);
  const auto precompute_start = std::chrono::steady_clock::now();
  auto stage_start = precompute_start;
  DirectionalBins bins = DirectionalBins::from_bin_count(settings.bins);
  BinSpreading spreading(bins);
  auto system = std::make_shared<AntiradiancePrecomputation>(std::move(bins), std::move(spreading));
  const int m = system->bins.bin_count();
  report.add_seconds("antiradiance_bins", seconds_since(stage_start));
  context.throw_if_cancelled();
  if (scene.triangles.empty()) return system;  // nothing to link; light() gives zero
  // Kept with the precomputation too, so that a cache hit repeats them.
  const auto warn = [&](const std::string& message) {
    report.warn(message);
    system->warnings.push_back(message);
  };

  // What the job's holdings (ray tracer, ...) and the spreading tables leave of the budget.
  const uint64_t available = inputs.memory.remaining_after(system->spreading.memory_bytes());
  const bool automatic = settings.patch_size == 0.0;
  // Automatic: extent / 16 (default_max_edge, element_hierarchy.cpp), coarsened while the estimate
  // exceeds kAutomaticElementLimit elements (a detailed scene otherwise multiplies elements and
  // links for little gain; the paper's office had 18k elements).
  const PatchCount count(scene);
  // The limit is a target, not a budget: it counts no back sides (the upper bound gives one to
  // every patch of an open mesh, and most get none: Sponza, 169 open meshes, 478 back sides
  // of 8,610 patches; counting them coarsened its patches to 8 m).
  float max_edge = automatic ? count.max_edge_within_budget(default_max_edge(scene),
                                                            kAutomaticElementLimit, false)
                             : float(settings.patch_size);
  if (!(max_edge > 0.0f) || !std::isfinite(max_edge)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "antiradiance: the scene has no extent to choose a patch size from");
  }
  const std::string budget_text = inputs.memory.describe();
  if (estimated_bytes(count, max_edge, m) > available) {
    const std::optional<float> fitting = patch_size_within(count, max_edge, m, available);
    if (!fitting) {
      const float coarsest = count.max_edge_within_budget(max_edge, 1);
      throw Error(
          BAKEGI_ERROR_OUT_OF_MEMORY,
          "antiradiance: even the coarsest patches (" + std::to_string(count.elements(coarsest)) +
              " elements at " + std::to_string(m) + " bins) need an estimated " +
              megabytes(estimated_bytes(count, coarsest, m)) + ", more than the budget of " +
              budget_text + " leaves; raise the budget or lower \"bins\"");
    }
    if (!automatic) {
      throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                  "antiradiance: patch size " + metres(max_edge) + " needs an estimated " +
                      megabytes(estimated_bytes(count, max_edge, m)) +
                      ", more than the budget of " + budget_text + " leaves; patch_size " +
                      metres(*fitting) + " (or 0 for automatic) would fit");
    }
    warn("antiradiance: patches coarsened from " + metres(max_edge) + " to " + metres(*fitting) +
         " to fit the memory budget of " + budget_text);
    max_edge = *fitting;
  }

  // Hierarchy and links; when the links turn out more than the estimate allowed, an automatic
  // patch size is coarsened once more.
  ElementHierarchy& hierarchy = system->hierarchy;
  LinkSet link_set;
  double hierarchy_seconds = 0.0, linking_seconds = 0.0;
  for (int attempt = 0;; ++attempt) {
    context.set_stage("antiradiance: hierarchy", 0.02, 0.04);
    stage_start = std::chrono::steady_clock::now();
    hierarchy = ElementHierarchy(
        scene, HierarchyOptions{max_edge, 0, &inputs.tracer, float(settings.glossy_fold_exponent)});
    hierarchy_seconds += seconds_since(stage_start);
    context.throw_if_cancelled();

    const uint64_t fixed = bytes_without_links(count, max_edge, m);
    const uint64_t max_links = available > fixed ? (available - fixed) / kPeakBytesPerLink : 0;
    context.set_stage("antiradiance: linking", 0.04, 0.40);
    stage_start = std::chrono::steady_clock::now();
    try {
      if (max_links == 0) {
        throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, "no room is left for links");
      }
      link_set = build_links(hierarchy, system->bins, system->spreading,
                             linking_options(settings, max_links), &context);
      linking_seconds += seconds_since(stage_start);
      break;
    } catch (const Error& e) {
      linking_seconds += seconds_since(stage_start);
      if (e.status() != BAKEGI_ERROR_OUT_OF_MEMORY) throw;
      const std::string what = "antiradiance: the links at patch size " + metres(max_edge) + " (" +
                               std::to_string(hierarchy.element_count()) + " elements, at most " +
                               std::to_string(max_links) +
                               " links) do not fit the memory budget of " + budget_text;
      if (!automatic || attempt > 0) {
        throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                    what + (automatic ? "; raise the budget or lower \"bins\""
                                      : "; choose a larger patch_size (or 0 for automatic)"));
      }
      warn(what + "; coarsened to " + metres(max_edge * 2.0f));
      max_edge *= 2.0f;
    }
  }
  system->link_statistics = link_set.statistics;
  for (const std::string& warning : open_mesh_warnings(scene, hierarchy.back_side_count() > 0)) {
    warn("antiradiance: " + warning);
  }
  context.throw_if_cancelled();

  stage_start = std::chrono::steady_clock::now();
  system->transport =
      GlobalPass(std::move(link_set.links), hierarchy.element_count(), system->spreading);
  link_set = LinkSet{};
  report.add_seconds("antiradiance_hierarchy", hierarchy_seconds);
  report.add_seconds("antiradiance_linking", linking_seconds);
  // Grouping the links by receiver.
  report.add_seconds("antiradiance_tables", seconds_since(stage_start));
  system->seconds = seconds_since(precompute_start);
  return system;
}

std::unique_ptr<IndirectField> AntiradianceSolver::light(
    const SolveInputs& inputs, std::shared_ptr<const Precomputation> precomputation,
    JobContext& context) {
  const auto* made = dynamic_cast<const AntiradiancePrecomputation*>(precomputation.get());
  if (!made) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "antiradiance: the precomputation to light was made by another method");
  }
  const AntiradiancePrecomputation& system = *made;
  const AntiradianceSettings settings = AntiradianceSettings::from(inputs.settings);
  if (system.hierarchy.element_count() == 0) {
    return std::make_unique<AntiradianceField>(SurfaceInterpolation{});
  }
  check_made_for(system.hierarchy, inputs.scene);
  Report& report = context.report();
  const ElementHierarchy& hierarchy = system.hierarchy;
  const DirectionalBins& bins = system.bins;
  const int m = bins.bin_count();

  auto stage_start = std::chrono::steady_clock::now();
  RadianceTables tables(hierarchy.element_count(), hierarchy.patch_count(), m);
  report.add_seconds("antiradiance_tables", seconds_since(stage_start));

  context.set_stage("antiradiance: direct light", 0.40, 0.60);
  stage_start = std::chrono::steady_clock::now();
  const DirectLightAtPatches direct = direct_light_at_patches(
      hierarchy, bins, inputs.direct, settings.direct_samples, uint64_t(settings.seed), context);
  initialize_direct(hierarchy, bins, direct, tables);
  const double direct_seconds = seconds_since(stage_start);
  context.throw_if_cancelled();

  context.set_stage("antiradiance: iterating", 0.60, 0.96);
  stage_start = std::chrono::steady_clock::now();
  IterationOptions options;
  options.scheme = settings.scheme;
  options.max_iterations = int(settings.iterations);
  options.tolerance = settings.tolerance;
  options.flux_bound = flux_bound(hierarchy, direct.irradiance);
  const IterationResult result =
      iterate(hierarchy, bins, system.spreading, system.transport, tables, options, &context);
  const double iterate_seconds = seconds_since(stage_start);
  context.throw_if_cancelled();
  // Diverging from the first bounces on, the kept state is little more than one bounce of
  // indirect light (a furnished room came out 31% low, Sponza 100% off): not a result to
  // give where the path tracer can give a right one.
  if (result.stopped_early && result.history.size() <= kUnusableIterations &&
      SettingReader(inputs.settings, method_schema("antiradiance")).get_int("fallback") != 0) {
    throw CannotModel("antiradiance: the iteration diverged (" + result.warning +
                      "); the method cannot model this scene at these settings");
  }
  if (!result.warning.empty()) report.warn("antiradiance: " + result.warning);

  context.set_stage("antiradiance: output", 0.96, 1.0);
  stage_start = std::chrono::steady_clock::now();
  std::vector<SurfaceSample> samples(hierarchy.patch_count());
  const std::span<const glm::vec3> irradiance = tables.accumulated_irradiance();
  for (size_t p = 0; p < samples.size(); ++p) {
    const Patch& patch = hierarchy.patches()[p];
    const Element& element = hierarchy.elements()[patch.element];
    SurfaceSample& s = samples[p];
    s.center = element.center;
    s.normal = glm::dot(patch.shading_normal, patch.shading_normal) > 0.5f ? patch.shading_normal
                                                                           : patch.normal;
    s.radius = element.radius;  // centre to the farthest corner (of any member)
    s.area = element.area;
    glm::vec3 value = irradiance[p] / std::numbers::pi_v<float>;
    // The output convention has no room for non-finite or negative light; iterate() warns
    // when its solution is unusable, this only keeps the field finite.
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(value[c])) value[c] = 0.0f;
    }
    s.value = glm::max(value, glm::vec3(0.0f));
  }
  // The near-field gather and the path-traced residual read the patch each ray hits.
  std::shared_ptr<const PatchRadianceCache> cache;
  if (settings.near_field_rays > 0 || settings.residual_path_traced) {
    std::vector<glm::vec3> direct_over_pi(samples.size()), indirect_over_pi(samples.size());
    for (size_t p = 0; p < samples.size(); ++p) {
      direct_over_pi[p] = direct.irradiance[p] / std::numbers::pi_v<float>;
      indirect_over_pi[p] = samples[p].value;
    }
    cache = std::make_shared<PatchRadianceCache>(
        inputs.scene, PatchLocator(inputs.scene, hierarchy), std::move(direct_over_pi),
        std::move(indirect_over_pi));
  }
  if (settings.residual_path_traced) {
    // The solution only serves as the path tracer's control variate (controlled_path.h).
    report.add_count("memory_bytes",
                     system.memory_bytes() + tables.memory_bytes() + cache->memory_bytes());
    report_solution(report, system, tables, result, direct_seconds, iterate_seconds);
    report.add_seconds("antiradiance_output", seconds_since(stage_start));
    return std::make_unique<ControlledPathField>(inputs.direct, std::move(cache),
                                                 PathTraceSettings::from(inputs.settings),
                                                 settings.residual_fraction);
  }
  NearFieldGather near_field;
  if (settings.near_field_rays > 0) {
    NearFieldSettings near_settings;
    near_settings.rays = uint32_t(settings.near_field_rays);
    near_settings.far = float(settings.near_field_distance) *
                        SurfaceInterpolation::kSupportInEdges * typical_patch_edge(samples);
    near_settings.near = 0.5f * near_settings.far;
    near_settings.ray_epsilon = inputs.direct.ray_epsilon();
    near_settings.seed = uint64_t(settings.seed) ^ 0x6e656172ull;
    near_field = NearFieldGather(inputs.direct, cache, near_settings);
  }
  SurfaceInterpolation interpolation(std::move(samples), &inputs.tracer);
  const double output_seconds = seconds_since(stage_start);

  report_solution(report, system, tables, result, direct_seconds, iterate_seconds);
  // The job's memory: what relighting keeps, the bin tables (the peak is during the
  // iteration), and the output field.
  report.add_count("memory_bytes", system.memory_bytes() + tables.memory_bytes() +
                                       interpolation.memory_bytes() +
                                       (cache ? cache->memory_bytes() : 0));
  report.set_number("antiradiance_support_radius", double(interpolation.support_radius()));
  report.add_seconds("antiradiance_output", output_seconds);
  return std::make_unique<AntiradianceField>(std::move(interpolation), std::move(near_field));
}

}  // namespace bakegi
