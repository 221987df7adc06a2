// The four passes of Antiradiance (§3.1–3.3, §4.2) on hand-built hierarchies and links:
// unoccluded transfer between two patches against the point-to-point analytic value,
// cancellation of light behind a blocker by its antiradiance (Fig. 3b, Fig. 4), push/pull as
// copy/sum, energy of one diffuse reflection, and a global pass independent of thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "light_transport_fixtures.h"
#include "scene/scene_validation.h"
#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/direct_initialization.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/global_pass.h"
#include "solvers/antiradiance/link.h"
#include "solvers/antiradiance/local_pass.h"
#include "solvers/antiradiance/push_pull.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

using antiradiance::BinSpreading;
using antiradiance::DirectionalBins;
using antiradiance::ElementHierarchy;
using antiradiance::GlobalPass;
using antiradiance::HierarchyOptions;
using antiradiance::Link;
using antiradiance::RadianceTables;

constexpr float kPi = std::numbers::pi_v<float>;

// An equilateral triangle of `area` centred at `centroid`, counter-clockwise around `normal`.
void add_triangle(SceneDescription& d, glm::vec3 centroid, glm::vec3 normal, float area,
                  uint32_t material) {
  normal = glm::normalize(normal);
  const glm::vec3 helper = std::abs(normal.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 u = glm::normalize(glm::cross(helper, normal));
  const glm::vec3 v = glm::cross(normal, u);  // u × v = normal
  const float side = std::sqrt(4.0f * area / std::sqrt(3.0f));
  const float circumradius = side / std::sqrt(3.0f);
  Mesh mesh;
  for (int k = 0; k < 3; ++k) {
    const float angle = kPi / 2.0f + float(k) * 2.0f * kPi / 3.0f;
    mesh.positions.push_back(centroid + circumradius * (std::cos(angle) * u + std::sin(angle) * v));
  }
  mesh.indices = {0, 1, 2};
  mesh.material = material;
  d.meshes.push_back(std::move(mesh));
}

// The passes take direct light as input, but a scene needs a light to be valid: a lamp far
// away that nothing here samples.
Scene build_scene_with_a_lamp(SceneDescription desc) {
  desc.lights.push_back(point_light({100, 100, 100}, glm::vec3(1.0f)));
  return build_scene(desc);
}

// Patches large enough that no input triangle is split.
ElementHierarchy unsplit_hierarchy(const Scene& scene) {
  HierarchyOptions options;
  options.max_edge = 100.0f;
  return ElementHierarchy(scene, options);
}

// The patch whose centroid is nearest `point`.
size_t patch_near(const ElementHierarchy& h, glm::vec3 point) {
  size_t best = 0;
  for (size_t p = 1; p < h.patch_count(); ++p) {
    if (glm::distance(h.elements()[h.patches()[p].element].center, point) <
        glm::distance(h.elements()[h.patches()[best].element].center, point)) {
      best = p;
    }
  }
  return best;
}

// The local pass divides E by the bins' discrete cosine sum instead of π / ω_bin (local_pass.h)
// so that a uniform field gives exactly π L: a transfer through single bins comes out scaled by
// π / (ω_bin Σ_l ⟨n|−ω_l⟩₊) for the receiver's normal n.
double cosine_normalization(const DirectionalBins& bins, glm::vec3 normal) {
  double sum = 0.0;
  for (int j = 0; j < bins.bin_count(); ++j) {
    sum += std::max(0.0, -double(glm::dot(normal, bins.direction(j))));
  }
  return std::numbers::pi / (bins.solid_angle() * sum);
}

// An unspread link from sender to receiver with the form factor of Eq. 17.
Link make_link(const ElementHierarchy& h, const DirectionalBins& bins, uint32_t sender,
               uint32_t receiver) {
  const glm::vec3 from = h.elements()[sender].center, to = h.elements()[receiver].center;
  Link link;
  link.sender = sender;
  link.receiver = receiver;
  link.bin = uint16_t(bins.bin_of(to - from));
  link.spread_class = 0;
  const float d = glm::distance(from, to);
  link.form_factor = float(1.0 / (double(d) * d * bins.solid_angle()));
  return link;
}

// One iteration after the initialization: global pass, push, local pass, pull.
void iterate(const ElementHierarchy& h, const DirectionalBins& bins, const BinSpreading& spreading,
             const GlobalPass& global, RadianceTables& tables) {
  global.run(spreading, tables);
  antiradiance::push(h, tables);
  antiradiance::local_pass(h, bins, tables);
  antiradiance::pull(h, tables);
}

TEST(AntiradiancePasses, TableBytesAreKnownBeforeAllocating) {
  // 27k elements at 192 bins: two tables of 62 MB.
  EXPECT_EQ(RadianceTables::bytes(27000, 13500, 192), 2ull * 27000 * 192 * 12 + 13500 * 12);
  EXPECT_EQ(RadianceTables::bytes(UINT64_MAX / 4, 0, 192), UINT64_MAX);
  const RadianceTables tables(100, 50, 48);
  EXPECT_GE(tables.memory_bytes(), RadianceTables::bytes(100, 50, 48));
}

TEST(AntiradiancePasses, TwoFacingPatchesExchangeThePointToPointIrradiance) {
  // Sender at the origin facing +z, receiver at distance d facing it; small patches so the
  // point-to-point value I cos / d² is the transfer being discretized.
  const float d = 3.0f, area = 0.01f, albedo = 0.6f, direct = 10.0f;
  SceneDescription desc;
  const uint32_t material = add_material(desc, glm::vec3(albedo));
  add_triangle(desc, {0, 0, 0}, {0, 0, 1}, area, material);
  add_triangle(desc, {0, 0, d}, {0, 0, -1}, area, material);
  const Scene scene = build_scene_with_a_lamp(desc);
  const ElementHierarchy h = unsplit_hierarchy(scene);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const size_t sender = patch_near(h, {0, 0, 0}), receiver = patch_near(h, {0, 0, d});
  const uint32_t se = h.patches()[sender].element, re = h.patches()[receiver].element;
  const GlobalPass global({make_link(h, bins, se, re), make_link(h, bins, re, se)},
                          h.element_count(), spreading);

  RadianceTables tables(h.element_count(), h.patch_count(), bins.bin_count());
  std::vector<glm::vec3> e_direct(h.patch_count(), glm::vec3(0.0f));
  e_direct[sender] = glm::vec3(direct);
  antiradiance::initialize_direct(h, bins, e_direct, tables);
  iterate(h, bins, spreading, global, tables);

  // Both ends see the exchange along the center of the link's bin, not along the axis: the
  // sender's intensity and the receiver's cosine each carry cos θ, θ the angle from the axis
  // to that bin center. Exact to float rounding against that:
  const int bin = bins.bin_of(glm::vec3(0, 0, 1));
  const float cos_theta = bins.direction(bin).z;
  const float a = h.elements()[se].area;
  const float point_to_point = a * albedo / kPi * direct / (d * d);
  const glm::vec3 received = tables.accumulated_irradiance()[receiver];
  const double normalization = cosine_normalization(bins, h.patches()[receiver].normal);
  EXPECT_NEAR(received.x, point_to_point * cos_theta * cos_theta * normalization,
              1e-5f * point_to_point);
  // Against the analytic value (normal incidence, cos = 1) the error is 1 − cos² θ. θ is at
  // most the distance from a bin's center to its farthest point, which for HEALPix stays
  // below twice the half-angle α of a cap of one bin's solid angle (polar pixels, the most
  // elongated, reach about 1.4 α at Nside 4).
  const double alpha = bins.bin_cone_half_angle();
  ASSERT_LE(std::acos(cos_theta), 2.0 * alpha);
  const double tolerance = 1.0 - std::pow(std::cos(2.0 * alpha), 2.0) + 0.25 * bins.solid_angle();
  EXPECT_NEAR(received.x, point_to_point, tolerance * point_to_point);
  EXPECT_EQ(received.x, received.y);
  // Nothing came back to the sender: the receiver had no light to reflect before.
  EXPECT_EQ(tables.accumulated_irradiance()[sender], glm::vec3(0.0f));
}

// Light from a sender S along one bin reaches a patch T behind a blocker B unoccluded (U
// knows no visibility); B's antiradiance, sent on along the same bin one iteration later,
// removes it (Fig. 3b, Fig. 4). The scene lies along a bin center so every cosine is 1 and
// the discrete quantities are exact. B gathers L_in = I / (d_SB² ω) and re-emits
// I_A = a_B L_in; T receives I / (d_ST² ω) from S and −I_A / (d_BT² ω) from B: they cancel
// when a_B = ω d_SB² d_BT² / d_ST² (the blocker fills the bin's cone, seen from T through B's
// center). A blocker of `area_fraction` of that lets 1 − area_fraction of the light through.
struct BlockerResult {
  float leaked_first_iteration;  // E at T after one iteration
  float total;                   // E at T summed over two iterations
  float unoccluded;  // I / d_ST² (times cosine_normalization), T's light without the blocker
  float blocker_back_intensity;  // I_ex of B along the bin after the first local pass
  float blocker_incident;        // L_in of B in that bin
  float blocker_area;
};

BlockerResult shine_past_blocker(float area_fraction) {
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const int bin = bins.bin_count() / 2 + 3;  // an equatorial-belt bin, nothing special
  const glm::vec3 axis = bins.direction(bin);
  const float d_sb = 1.0f, d_st = 3.0f, d_bt = d_st - d_sb, direct = 10.0f, albedo = 0.5f;
  const float blocker_area =
      area_fraction * float(bins.solid_angle()) * d_sb * d_sb * d_bt * d_bt / (d_st * d_st);
  SceneDescription desc;
  const uint32_t material = add_material(desc, glm::vec3(albedo));
  add_triangle(desc, glm::vec3(0.0f), axis, 0.001f, material);
  add_triangle(desc, d_sb * axis, -axis, blocker_area, material);
  add_triangle(desc, d_st * axis, -axis, 0.001f, material);
  const Scene scene = build_scene_with_a_lamp(desc);
  const ElementHierarchy h = unsplit_hierarchy(scene);
  const size_t s = patch_near(h, glm::vec3(0.0f)), b = patch_near(h, d_sb * axis),
               t = patch_near(h, d_st * axis);
  const uint32_t se = h.patches()[s].element, be = h.patches()[b].element,
                 te = h.patches()[t].element;
  std::vector<Link> links = {make_link(h, bins, se, be), make_link(h, bins, se, te),
                             make_link(h, bins, be, te)};
  for (const Link& link : links) EXPECT_EQ(link.bin, bin);
  const GlobalPass global(std::move(links), h.element_count(), spreading);

  RadianceTables tables(h.element_count(), h.patch_count(), bins.bin_count());
  std::vector<glm::vec3> e_direct(h.patch_count(), glm::vec3(0.0f));
  e_direct[s] = glm::vec3(direct);
  antiradiance::initialize_direct(h, bins, e_direct, tables);
  const float intensity = tables.exitant(se)[size_t(bin)].x;

  BlockerResult r;
  iterate(h, bins, spreading, global, tables);
  r.leaked_first_iteration = tables.accumulated_irradiance()[t].x;
  r.blocker_back_intensity = tables.exitant(be)[size_t(bin)].x;
  r.blocker_incident = tables.incident(be)[size_t(bin)].x;
  r.blocker_area = h.elements()[be].area;
  iterate(h, bins, spreading, global, tables);
  r.total = tables.accumulated_irradiance()[t].x;
  r.unoccluded =
      float(intensity / (d_st * d_st) * cosine_normalization(bins, h.patches()[t].normal));
  return r;
}

TEST(AntiradiancePasses, AntiradianceOfAFullBlockerCancelsTheLightBehindIt) {
  const BlockerResult r = shine_past_blocker(1.0f);
  ASSERT_GT(r.unoccluded, 0.0f);
  // The first iteration knows no blocker: T gets the unoccluded light (Fig. 3b's leak).
  EXPECT_NEAR(r.leaked_first_iteration, r.unoccluded, 1e-5f * r.unoccluded);
  // Eq. 19: what arrived at B's front leaves its back along the same bin as −I_A.
  EXPECT_NEAR(r.blocker_back_intensity, -r.blocker_area * r.blocker_incident,
              1e-5f * r.blocker_area * r.blocker_incident);
  // The second iteration brings B's antiradiance: the sum vanishes up to float rounding
  // of the triangle's area and the cosines (~1e-6 relative each).
  EXPECT_NEAR(r.total, 0.0f, 1e-4f * r.unoccluded);
}

TEST(AntiradiancePasses, AHalfBlockerRemovesHalfTheLight) {
  const BlockerResult r = shine_past_blocker(0.5f);
  EXPECT_NEAR(r.total, 0.5f * r.unoccluded, 1e-4f * r.unoccluded);
}

// A room of six quads split into many patches: a hierarchy several levels deep.
ElementHierarchy box_hierarchy(Scene& scene_storage, float max_edge) {
  SceneDescription desc;
  const uint32_t white = add_material(desc, glm::vec3(0.7f));
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  add_quad(desc, {0, 0, 0}, x, y, 1, 1, white);
  add_quad(desc, {0, 0, 2}, y, x, 1, 1, white);
  add_quad(desc, {0, 1, 1}, z, x, 1, 1, white);
  add_quad(desc, {0, -1, 1}, x, z, 1, 1, white);
  add_quad(desc, {-1, 0, 1}, y, z, 1, 1, white);
  add_quad(desc, {1, 0, 1}, z, y, 1, 1, white);
  scene_storage = build_scene_with_a_lamp(desc);
  HierarchyOptions options;
  options.max_edge = max_edge;
  return ElementHierarchy(scene_storage, options);
}

TEST(AntiradiancePasses, PullSumsIntensityAndPushCopiesRadiance) {
  Scene scene;
  const ElementHierarchy h = box_hierarchy(scene, 0.5f);
  ASSERT_GT(h.element_count(), 1000u);  // deep enough to split into parallel subtrees
  const int m = 48;
  RadianceTables tables(h.element_count(), h.patch_count(), m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  const auto& elements = h.elements();
  for (size_t e = 0; e < h.element_count(); ++e) {
    for (auto& v : tables.incident(e)) v = {uniform(rng), uniform(rng), uniform(rng)};
    for (auto& v : tables.exitant(e)) {
      // Clusters hold garbage that pull must overwrite.
      v = elements[e].is_patch ? glm::vec3(uniform(rng), uniform(rng), uniform(rng))
                               : glm::vec3(1e6f);
    }
  }
  std::vector<glm::vec3> incident_before(h.element_count() * m);
  for (size_t e = 0; e < h.element_count(); ++e) {
    std::copy(tables.incident(e).begin(), tables.incident(e).end(),
              incident_before.begin() + e * m);
  }
  antiradiance::pull(h, tables);
  antiradiance::push(h, tables);
  // Rounding: sums of up to ~3000 terms of magnitude 1 in float, a few 1e-4 at most; the
  // check recomputes in double.
  for (size_t e = 0; e < h.element_count(); ++e) {
    for (int j = 0; j < m; j += 7) {
      glm::dvec3 patch_sum(0.0);
      for (size_t k = e; k < elements[e].subtree_end; ++k) {
        if (elements[k].is_patch) patch_sum += glm::dvec3(tables.exitant(k)[j]);
      }
      EXPECT_NEAR(tables.exitant(e)[j].x, patch_sum.x, 1e-3) << "element " << e;
      glm::dvec3 ancestor_sum(0.0);
      for (uint32_t k = uint32_t(e); k != antiradiance::kNoElement; k = elements[k].parent) {
        ancestor_sum += glm::dvec3(incident_before[k * m + j]);
      }
      EXPECT_NEAR(tables.incident(e)[j].z, ancestor_sum.z, 1e-4) << "element " << e;
    }
  }
}

TEST(AntiradiancePasses, OneDiffuseReflectionReflectsAlbedoTimesIncidentFlux) {
  const float albedo = 0.7f, area = 0.25f;
  for (const int requested : {48, 192, 768}) {
    const DirectionalBins bins = DirectionalBins::from_bin_count(requested);
    const double omega = bins.solid_angle();
    // A tilted normal, so no symmetry of the bin layout helps.
    const glm::vec3 normal = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    SceneDescription desc;
    add_triangle(desc, {0, 0, 0}, normal, area, add_material(desc, glm::vec3(albedo)));
    const Scene scene = build_scene_with_a_lamp(desc);
    const ElementHierarchy h = unsplit_hierarchy(scene);
    ASSERT_EQ(h.patch_count(), 1u);
    const uint32_t e = h.patches()[0].element;
    const glm::vec3 n = h.patches()[0].normal;
    RadianceTables tables(h.element_count(), h.patch_count(), bins.bin_count());
    // Incident radiance varying over the sphere, in both hemispheres.
    double expected_e = 0.0, quadrature_of_cos = 0.0;
    for (int j = 0; j < bins.bin_count(); ++j) {
      const glm::vec3 w = bins.direction(j);
      const float radiance = 1.0f + 0.5f * w.x + 0.25f * w.y * w.z;
      tables.incident(e)[j] = glm::vec3(radiance);
      const double c = glm::dot(n, w);
      if (c < 0.0) expected_e += -c * radiance * omega;
      if (c > 0.0) quadrature_of_cos += c * omega;
    }
    const double unnormalized_e = expected_e;  // what J passes on through the back
    expected_e *= cosine_normalization(bins, n);
    antiradiance::local_pass(h, bins, tables);
    const float e_local = tables.accumulated_irradiance()[0].x;
    EXPECT_NEAR(e_local, expected_e, 1e-5 * expected_e);
    double reflected_flux = 0.0, back_flux = 0.0;
    for (int j = 0; j < bins.bin_count(); ++j) {
      const double c = glm::dot(n, bins.direction(j));
      const double i_ex = tables.exitant(e)[j].x;
      if (c > 0.0) reflected_flux += i_ex * omega;
      // Antiradiance: the back hemisphere continues the incident radiance (Eq. 19).
      if (c < 0.0) EXPECT_NEAR(i_ex, area * c * tables.incident(e)[j].x, 1e-6);
      if (c < 0.0) back_flux += i_ex * omega;
    }
    // Flux in the reflected lobe: ρ E a times the bin quadrature of ∫ cos = π, exactly.
    const double incident_flux = expected_e * h.elements()[e].area;
    EXPECT_NEAR(reflected_flux, albedo * incident_flux * quadrature_of_cos / std::numbers::pi,
                1e-5 * incident_flux);
    // The quadrature of the clamped cosine: the midpoint rule is exact for the linear part
    // (HEALPix centers come in antipodal pairs), the error comes from the band of bins
    // straddling the horizon, where the kink lies, and shrinks like ω_bin. Measured over axis,
    // diagonal and tilted normals at 48–768 bins: |Σ/π − 1| ≤ 0.11 ω_bin; we allow 0.25 ω_bin.
    EXPECT_NEAR(quadrature_of_cos / std::numbers::pi, 1.0, 0.25 * omega) << requested << " bins";
    // The antiradiance flux is minus the incident flux.
    EXPECT_NEAR(back_flux, -unnormalized_e * h.elements()[e].area, 1e-5 * incident_flux);
  }
}

TEST(AntiradiancePasses, GlobalPassIsIndependentOfThreadCountAndMatchesTheDefinition) {
  Scene scene;
  const ElementHierarchy h = box_hierarchy(scene, 0.25f);
  const size_t n = h.element_count();
  const DirectionalBins bins = DirectionalBins::from_bin_count(48);
  const BinSpreading spreading(bins);
  std::mt19937 rng(11);
  std::uniform_int_distribution<uint32_t> element(0, uint32_t(n - 1));
  std::uniform_int_distribution<int> bin(0, bins.bin_count() - 1);
  std::uniform_int_distribution<int> cone(0, spreading.class_count() - 1);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<Link> links(20000);
  for (Link& link : links) {
    link.receiver = element(rng);
    link.sender = element(rng);
    link.bin = uint16_t(bin(rng));
    link.spread_class = uint8_t(cone(rng));
    link.form_factor = uniform(rng);
  }
  const std::vector<Link> input = links;
  const GlobalPass global(std::move(links), n, spreading);

  RadianceTables tables(n, h.patch_count(), bins.bin_count());
  for (size_t e = 0; e < n; ++e) {
    for (auto& v : tables.exitant(e)) v = {uniform(rng), uniform(rng), uniform(rng)};
    for (auto& v : tables.incident(e)) v = glm::vec3(1e6f);  // must be cleared
  }
  auto run_with_threads = [&](int threads) {
    tbb::task_arena arena(threads);
    arena.execute([&] { global.run(spreading, tables); });
    std::vector<glm::vec3> out;
    for (size_t e = 0; e < n; ++e) {
      out.insert(out.end(), tables.incident(e).begin(), tables.incident(e).end());
    }
    return out;
  };
  const std::vector<glm::vec3> one = run_with_threads(1);
  EXPECT_EQ(run_with_threads(2), one);

  // Against the definition, summed in double in any order (float rounding of sums of a few
  // dozen positive terms: well below 1e-5 relative).
  std::vector<glm::dvec3> reference(n * size_t(bins.bin_count()), glm::dvec3(0.0));
  for (const Link& link : input) {
    const auto filter = spreading.filter(link.spread_class, link.bin);
    for (size_t f = 0; f < filter.bins.size(); ++f) {
      reference[link.receiver * bins.bin_count() + filter.bins[f]] +=
          double(filter.weights[f]) * double(link.form_factor) *
          glm::dvec3(tables.exitant(link.sender)[link.bin]);
    }
  }
  for (size_t k = 0; k < reference.size(); ++k) {
    EXPECT_NEAR(one[k].y, reference[k].y, 1e-5 * (1.0 + reference[k].y));
  }
}

TEST(AntiradiancePasses, GlobalPassRejectsLinksOutsideTheTables) {
  const DirectionalBins bins(2);
  const BinSpreading spreading(bins);
  Link link;
  link.receiver = 5;
  EXPECT_THROW(GlobalPass({link}, 5, spreading), Error);
  link.receiver = 0;
  link.bin = uint16_t(bins.bin_count());
  EXPECT_THROW(GlobalPass({link}, 5, spreading), Error);
  link.bin = 0;
  const GlobalPass global({link}, 5, spreading);
  RadianceTables wrong(4, 0, bins.bin_count());
  EXPECT_THROW(global.run(spreading, wrong), Error);
}

// Emission is left out of I_ex: emitters reach receivers as direct light already.
TEST(AntiradiancePasses, DirectInitializationSeedsReflectedDirectLightOnly) {
  SceneDescription desc;
  const glm::vec3 emission(2.0f, 1.0f, 0.5f);
  add_triangle(desc, {0, 0, 0}, {0, 0, 1}, 0.5f, add_material(desc, glm::vec3(0.5f), emission));
  add_triangle(desc, {2, 0, 0}, {1, 0, 0}, 0.5f, add_material(desc, glm::vec3(0.8f)));
  const Scene scene = build_scene_with_a_lamp(desc);
  const ElementHierarchy h = unsplit_hierarchy(scene);
  const DirectionalBins bins(3);
  RadianceTables tables(h.element_count(), h.patch_count(), bins.bin_count());
  tables.accumulated_irradiance()[0] = glm::vec3(5.0f);  // a previous solution
  const std::vector<glm::vec3> e_direct = {glm::vec3(3.0f), glm::vec3(4.0f)};
  antiradiance::initialize_direct(h, bins, e_direct, tables);
  for (size_t p = 0; p < h.patch_count(); ++p) {
    const auto& patch = h.patches()[p];
    const float a = h.elements()[patch.element].area;
    const glm::vec3 radiance = patch.albedo / kPi * e_direct[p];
    for (int j = 0; j < bins.bin_count(); ++j) {
      const float c = glm::dot(patch.normal, bins.direction(j));
      const glm::vec3 expected = c > 0.0f ? a * c * radiance : glm::vec3(0.0f);
      const glm::vec3 got = tables.exitant(patch.element)[j];
      EXPECT_NEAR(got.x, expected.x, 1e-6f);
      EXPECT_NEAR(got.z, expected.z, 1e-6f);
    }
    EXPECT_EQ(tables.accumulated_irradiance()[p], glm::vec3(0.0f));
  }
  // The root got the pull: the sum of both patches.
  for (int j = 0; j < bins.bin_count(); ++j) {
    const glm::vec3 sum =
        tables.exitant(h.patches()[0].element)[j] + tables.exitant(h.patches()[1].element)[j];
    EXPECT_NEAR(tables.exitant(0)[j].y, sum.y, 1e-6f);
  }
}

TEST(AntiradiancePasses, DirectIrradianceAtPatchesMatchesAPointLight) {
  // A point light of intensity I at height h above a patch facing it: E = I / h².
  SceneDescription desc;
  add_triangle(desc, {0, 0, 0}, {0, 0, 1}, 0.01f, add_material(desc, glm::vec3(0.5f)));
  const float height = 2.0f, intensity = 8.0f;
  desc.lights.push_back(point_light({0, 0, height}, glm::vec3(intensity)));
  Baker baker(desc);
  const ElementHierarchy h = unsplit_hierarchy(baker.scene());
  JobContext context;
  const auto e = antiradiance::direct_irradiance_at_patches(h, baker.direct(), 4, 0, context);
  ASSERT_EQ(e.size(), 1u);
  // A delta light: every sample is exact up to float rounding.
  EXPECT_NEAR(e[0].x, intensity / (height * height), 1e-4f * intensity);
  EXPECT_GT(context.report().count("rays"), 0u);
}

}  // namespace
}  // namespace bakegi::test
