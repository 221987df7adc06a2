// Antiradiance link refinement (paper §3.2, Eq. 15–17, Fig. 7): two small patches exchange the
// irradiance of Eq. 15, solids receive nothing from behind, the oracle holds on every kept
// link, and the links of a patch and of its ancestors see every other patch exactly once.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "light_transport_fixtures.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/link_refinement.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::test {
namespace {

using antiradiance::BinSpreading;
using antiradiance::build_links;
using antiradiance::DirectionalBins;
using antiradiance::Element;
using antiradiance::ElementHierarchy;
using antiradiance::HierarchyOptions;
using antiradiance::Link;
using antiradiance::LinkingOptions;
using antiradiance::LinkSet;
using antiradiance::OracleExtent;
using antiradiance::SpreadFilter;

// One triangle with legs `leg` along x and y from `origin`, facing +z, or -z when `flipped`.
Mesh triangle(glm::vec3 origin, float leg, bool flipped, uint32_t material) {
  Mesh mesh;
  mesh.positions = {origin, origin + glm::vec3(leg, 0, 0), origin + glm::vec3(0, leg, 0)};
  mesh.indices = flipped ? std::vector<uint32_t>{0, 2, 1} : std::vector<uint32_t>{0, 1, 2};
  mesh.material = material;
  return mesh;
}

// Two triangles of leg `leg`, one at z = 0 and one straight above it at z = d, each facing
// +z or -z as asked.
SceneDescription two_patches(float leg, float d, bool lower_up, bool upper_up) {
  SceneDescription s;
  const uint32_t material = add_material(s, {0.5f, 0.5f, 0.5f});
  s.meshes.push_back(triangle({0, 0, 0}, leg, !lower_up, material));
  s.meshes.push_back(triangle({0, 0, d}, leg, !upper_up, material));
  s.lights.push_back(point_light({0.3f, 0.3f, 0.5f * d}, glm::vec3(1.0f)));
  return s;
}

SceneDescription closed_room() {
  SceneDescription s;
  const uint32_t material = add_material(s, {0.5f, 0.5f, 0.5f});
  s.meshes.push_back(make_cube({0, 0, 0}, {1, 1, 1}, Facing::kInward, material));
  s.lights.push_back(point_light({0.5f, 0.5f, 0.5f}, glm::vec3(1.0f)));
  return s;
}

// A Cornell-box-like room (as in the hierarchy tests): five walls facing inwards, two boxes.
SceneDescription cornell_like() {
  SceneDescription d;
  const uint32_t white = add_material(d, {0.725f, 0.71f, 0.68f});
  const uint32_t red = add_material(d, {0.63f, 0.065f, 0.05f});
  const uint32_t green = add_material(d, {0.14f, 0.45f, 0.091f});
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  add_quad(d, {0, 0, 0}, x, y, 1, 1, white);
  add_quad(d, {0, 0, 2}, y, x, 1, 1, white);
  add_quad(d, {0, 1, 1}, z, x, 1, 1, white);
  add_quad(d, {-1, 0, 1}, y, z, 1, 1, red);
  add_quad(d, {1, 0, 1}, z, y, 1, 1, green);
  auto box = [&](glm::vec3 lo, glm::vec3 hi) {
    Mesh room = make_cube(lo, hi, Facing::kInward, white);
    // Outward-facing: reverse the winding of the inward room.
    for (size_t t = 0; t < room.indices.size(); t += 3)
      std::swap(room.indices[t + 1], room.indices[t + 2]);
    d.meshes.push_back(room);
  };
  box({0.03f, -0.67f, 0}, {0.63f, -0.07f, 0.6f});
  box({-0.64f, -0.01f, 0}, {-0.04f, 0.59f, 1.2f});
  d.lights.push_back(point_light({0, 0, 1.9f}, glm::vec3(10.0f)));
  return d;
}

bool is_ancestor_or_self(const std::vector<Element>& elements, uint32_t a, uint32_t b) {
  return a <= b && b < elements[a].subtree_end;
}

// The oracle's measure (link_refinement.h): π r²/d² for kBoundingSphere; for kProjectedArea a
// patch's projected area, a cluster's min(π r², area), over d².
double oracle_solid_angle(const ElementHierarchy& h, uint32_t e, const glm::dvec3& direction,
                          double d2, OracleExtent extent = LinkingOptions{}.extent) {
  const Element& element = h.elements()[e];
  if (extent == OracleExtent::kBoundingSphere) {
    return std::numbers::pi * double(element.radius) * element.radius / d2;
  }
  if (element.is_patch) {
    const glm::dvec3 n(h.patches()[element.patch].normal);
    return double(element.area) * std::abs(glm::dot(n, glm::normalize(direction))) / d2;
  }
  return std::min(std::numbers::pi * double(element.radius) * element.radius,
                  double(element.area)) /
         d2;
}

// Every kept link: the travel-direction bin of its centers and the Eq. 17 form factor, which
// only patch pairs closer than twice their radii may lower (the near-field bound): further
// apart, the point model a |cos| cos / d² ≤ π r² / (4 r²) stays below the bound of π/2.
void expect_link_geometry(const ElementHierarchy& h, const DirectionalBins& bins,
                          const std::vector<Link>& links) {
  for (const Link& link : links) {
    const Element& r = h.elements()[link.receiver];
    const Element& k = h.elements()[link.sender];
    const glm::dvec3 travel = glm::dvec3(r.center) - glm::dvec3(k.center);
    const double d2 = glm::dot(travel, travel);
    const double eq17 = link.form_factor * d2 * bins.solid_angle();
    // Computed in double, stored as float: one float rounding.
    if (!r.is_patch || !k.is_patch || std::sqrt(d2) >= 2.0 * (r.radius + k.radius)) {
      EXPECT_NEAR(eq17, 1.0, 1e-6);
    } else {
      EXPECT_GT(eq17, 0.0);
      EXPECT_LE(eq17, 1.0 + 1e-6);
    }
    EXPECT_EQ(link.bin, bins.bin_of(travel));
  }
}

// ∫ ⟨n|ω⟩₊ dω over the triangle (a, b, c) seen from x with normal n, by the midpoint rule on
// `cells`² sub-triangles of the barycentric grid: Σ cos_x cos_t / r² dA, with cos_t the
// triangle's own cosine.
double projected_solid_angle_by_quadrature(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 x,
                                           glm::dvec3 n, int cells) {
  const glm::dvec3 u = (b - a) / double(cells), v = (c - a) / double(cells);
  const glm::dvec3 cross = glm::cross(u, v);
  const double cell_area = 0.5 * glm::length(cross);
  const glm::dvec3 normal_t = glm::normalize(cross);
  double sum = 0.0;
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; i + j < cells; ++j) {
      const glm::dvec3 centroids[2] = {a + (i + 1.0 / 3) * u + (j + 1.0 / 3) * v,
                                       a + (i + 2.0 / 3) * u + (j + 2.0 / 3) * v};
      for (int t = 0; t < (i + j + 1 < cells ? 2 : 1); ++t) {
        const glm::dvec3 r = centroids[t] - x;
        const double r2 = glm::dot(r, r), length = std::sqrt(r2);
        const double cos_x = glm::dot(n, r) / length;
        if (cos_x <= 0.0) continue;
        sum += cos_x * std::abs(glm::dot(normal_t, r)) / length / r2 * cell_area;
      }
    }
  }
  return sum;
}

TEST(AntiradianceLinking, TwoFacingPatchesExchangeTheIrradianceOfEq15) {
  const float leg = 0.02f, d = 1.0f;
  const Scene scene = build_scene(two_patches(leg, d, /*lower_up=*/true, /*upper_up=*/false));
  const ElementHierarchy h(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(h.patch_count(), 2u);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  ASSERT_EQ(set.links.size(), 2u);
  EXPECT_EQ(set.statistics.link_count, 2u);

  const uint32_t lower = h.patches()[0].element, upper = h.patches()[1].element;
  ASSERT_LT(h.elements()[lower].center.z, h.elements()[upper].center.z);
  const double omega = bins.solid_angle();
  for (const Link& link : set.links) {
    const bool upward = link.receiver == upper;
    EXPECT_EQ(link.sender, upward ? lower : upper);
    EXPECT_EQ(link.bin, bins.bin_of(glm::vec3(0, 0, upward ? 1.0f : -1.0f)));
    EXPECT_NEAR(link.form_factor, 1.0 / (double(d) * d * omega), 1e-6 / (d * d * omega));
    EXPECT_EQ(link.spread_class, 0);  // the sender covers far less than one bin
  }

  // Physics: a sender of radiance 1 facing the receiver has intensity I = A_k (Eq. 18, cosine
  // 1). The incident radiance of the link times the bin's solid angle is the irradiance at
  // the receiver's center, which for a small sender must match ∫ cos cos / r² dA_k. Compute
  // that integral by the midpoint rule on 128² sub-triangles (error far below 1e-6).
  const double area = 0.5 * double(leg) * leg;
  const double irradiance_from_link = area * set.links[0].form_factor * omega;
  const glm::dvec3 receiver(h.elements()[upper].center);
  double exact = 0.0;
  const int n = 128;
  const double h_step = double(leg) / n, cell_area = 0.5 * h_step * h_step;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; a + b < n; ++b) {
      // The two sub-triangles of cell (a, b): lower-left always, upper-right if inside.
      const double centroids[2][2] = {{(a + 1.0 / 3) * h_step, (b + 1.0 / 3) * h_step},
                                      {(a + 2.0 / 3) * h_step, (b + 2.0 / 3) * h_step}};
      for (int t = 0; t < (a + b + 1 < n ? 2 : 1); ++t) {
        const glm::dvec3 r = receiver - glm::dvec3(centroids[t][0], centroids[t][1], 0.0);
        const double r2 = glm::dot(r, r), cos_theta = r.z / std::sqrt(r2);
        exact += cos_theta * cos_theta / r2 * cell_area;
      }
    }
  }
  // Contracting the sender to its center errs by O((size/d)²) = O(4e-4) relative.
  EXPECT_NEAR(irradiance_from_link / exact, 1.0, 1e-3);
  // Eq. 15 directly: flux per receiver area = I / d².
  EXPECT_NEAR(irradiance_from_link, area / (double(d) * d), 1e-6 * area);
}

TEST(AntiradianceLinking, APatchFacingAwaySendsAntiradianceButReceivesNothing) {
  // Lower faces up (towards the upper patch), upper faces up (its back towards the lower).
  const Scene scene = build_scene(two_patches(0.02f, 1.0f, true, true));
  const ElementHierarchy h(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(h.patch_count(), 2u);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  // Fig. 7b: the upper patch's bins towards the lower one are in its negative hemisphere, so
  // they only send (antiradiance, down to the lower patch); the lower one's light arrives at
  // the upper one's back and is not received.
  ASSERT_EQ(set.links.size(), 1u);
  EXPECT_EQ(set.links[0].receiver, h.patches()[0].element);
  EXPECT_EQ(set.links[0].sender, h.patches()[1].element);
  EXPECT_EQ(set.links[0].bin, bins.bin_of(glm::vec3(0, 0, -1)));
  EXPECT_EQ(set.statistics.culled_behind_receiver, 1u);
}

TEST(AntiradianceLinking, PatchesFacingAwayFromEachOtherExchangeNothing) {
  const Scene scene = build_scene(two_patches(0.02f, 1.0f, false, true));
  const ElementHierarchy h(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(h.patch_count(), 2u);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  EXPECT_TRUE(set.links.empty());
  EXPECT_EQ(set.statistics.culled_behind_receiver, 2u);
  // Without the solid assumption both directions are linked.
  EXPECT_EQ(build_links(h, bins, spreading, LinkingOptions{0, false}).links.size(), 2u);
}

TEST(AntiradianceLinking, TheSelfLinkOfOnePatchYieldsNothing) {
  SceneDescription s;
  const uint32_t material = add_material(s, {0.5f, 0.5f, 0.5f});
  s.meshes.push_back(triangle({0, 0, 0}, 0.1f, false, material));
  s.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
  const Scene scene = build_scene(s);
  const ElementHierarchy h(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(h.element_count(), 1u);
  const DirectionalBins bins = DirectionalBins::from_bin_count(48);
  const BinSpreading spreading(bins);
  EXPECT_TRUE(build_links(h, bins, spreading, LinkingOptions{0, false}).links.empty());
}

TEST(AntiradianceLinking, ABigCloseSenderIsRefinedUntilTheOracleHolds) {
  // A 2 m square floor of patches with 0.0625 m legs and a small patch 0.15 m above its
  // center, facing it.
  SceneDescription s;
  const uint32_t material = add_material(s, {0.5f, 0.5f, 0.5f});
  add_quad(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1.0f, 1.0f, material);
  s.meshes.push_back(triangle({0.01f, 0.01f, 0.15f}, 0.02f, true, material));
  s.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
  const Scene scene = build_scene(s);
  const ElementHierarchy h(scene, HierarchyOptions{0.1f, 0});
  const auto& elements = h.elements();
  uint32_t small = antiradiance::kNoElement;
  for (const auto& p : h.patches()) {
    if (p.normal.z < 0.0f) small = p.element;
  }
  ASSERT_NE(small, antiradiance::kNoElement);

  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  ASSERT_FALSE(set.links.empty());
  expect_link_geometry(h, bins, set.links);
  const double omega = bins.solid_angle();
  const double threshold = LinkingOptions{}.oracle_factor * omega;
  size_t links_to_small = 0, wide = 0;
  for (const Link& link : set.links) {
    const Element& r = elements[link.receiver];
    const Element& k = elements[link.sender];
    const glm::dvec3 between = glm::dvec3(r.center) - glm::dvec3(k.center);
    const double d2 = glm::dot(between, between);
    const double sender_angle = oracle_solid_angle(h, link.sender, between, d2);
    const double receiver_angle = oracle_solid_angle(h, link.receiver, between, d2);
    if (!(r.is_patch && k.is_patch)) {
      EXPECT_LE(sender_angle, threshold);
      EXPECT_LE(receiver_angle, threshold);
    }
    EXPECT_EQ(link.spread_class, spreading.class_of(sender_angle));
    if (sender_angle > omega) ++wide;
    EXPECT_FALSE(is_ancestor_or_self(elements, link.receiver, link.sender));
    EXPECT_FALSE(is_ancestor_or_self(elements, link.sender, link.receiver));
    if (link.receiver == small) ++links_to_small;
  }
  EXPECT_EQ(wide, set.statistics.patch_pairs_kept_wide);
  // The floor right below is far wider than a bin: it must be split into many senders, down
  // to patches right below, which still cover more than a bin (radius ~0.04 m at 0.15 m:
  // π r²/d² ≈ 0.2 sr against 4π/192 ≈ 0.065 sr) and so are kept wide, with spreading.
  EXPECT_GT(links_to_small, 20u);
  EXPECT_GT(wide, 0u);
  EXPECT_GT(spreading.class_count(), 1);
}

// For every receiver patch p and sender patch q: how many links deliver q's light to p,
// directly or through an ancestor of p (pushed down). counts[p * P + q].
std::vector<int> coverage(const ElementHierarchy& h, const std::vector<Link>& links) {
  const auto& elements = h.elements();
  const size_t patches = h.patch_count();
  std::vector<int> counts(patches * patches, 0);
  for (const Link& link : links) {
    for (uint32_t r = link.receiver; r < elements[link.receiver].subtree_end; ++r) {
      if (!elements[r].is_patch) continue;
      for (uint32_t s = link.sender; s < elements[link.sender].subtree_end; ++s) {
        if (elements[s].is_patch) ++counts[elements[r].patch * patches + elements[s].patch];
      }
    }
  }
  return counts;
}

TEST(AntiradianceLinking, EveryPatchSeesEveryOtherPatchOfAClosedRoomExactlyOnce) {
  const Scene scene = build_scene(closed_room());
  // Face diagonals of 1.41 m split twice: 16 patches per triangle, 192 in all.
  const ElementHierarchy h(scene, HierarchyOptions{0.4f, 0});
  const size_t patches = h.patch_count();
  ASSERT_EQ(patches, 192u);
  // Every oracle variant: the default (bounding spheres, both ends), the projected areas at
  // half a bin, and a coarse sender-only one.
  LinkingOptions projected, coarse_sender_only;
  projected.extent = coarse_sender_only.extent = OracleExtent::kProjectedArea;
  projected.oracle_factor = 0.5;
  coarse_sender_only.test_receiver = false;
  coarse_sender_only.oracle_factor = 2.0;
  for (const LinkingOptions& oracle : {LinkingOptions{}, projected, coarse_sender_only}) {
    for (int bin_count : {48, 192}) {
      SCOPED_TRACE(bin_count);
      SCOPED_TRACE(oracle.oracle_factor);
      const DirectionalBins bins = DirectionalBins::from_bin_count(bin_count);
      const BinSpreading spreading(bins);

      // Without culling, the links are a partition of all patch pairs: no gaps, no double
      // counting, nothing from a patch to itself.
      LinkingOptions without_culling = oracle;
      without_culling.cull_behind_receiver = false;
      const LinkSet all = build_links(h, bins, spreading, without_culling);
      expect_link_geometry(h, bins, all.links);
      const std::vector<int> full = coverage(h, all.links);
      for (size_t p = 0; p < patches; ++p) {
        for (size_t q = 0; q < patches; ++q) {
          ASSERT_EQ(full[p * patches + q], p == q ? 0 : 1) << p << " " << q;
        }
      }
      // The hierarchy pays: far fewer links than patch pairs.
      EXPECT_LT(all.links.size(), patches * (patches - 1));

      // With the solid assumption: every point of a convex room is in front of every wall, so
      // only coplanar pairs (same wall) may lose their exchange; nothing counts twice.
      const LinkSet solid = build_links(h, bins, spreading, oracle);
      const std::vector<int> culled = coverage(h, solid.links);
      for (size_t p = 0; p < patches; ++p) {
        const auto& pp = h.patches()[p];
        for (size_t q = 0; q < patches; ++q) {
          const auto& pq = h.patches()[q];
          const float offset = glm::dot(
              pp.normal, h.elements()[pq.element].center - h.elements()[pp.element].center);
          const bool coplanar = std::abs(offset) < 1e-5f;
          if (coplanar) {
            ASSERT_LE(culled[p * patches + q], 1);
          } else {
            ASSERT_EQ(culled[p * patches + q], 1) << p << " " << q;
          }
        }
      }
      // No link lets a patch receive from a sender on its own plane or behind it.
      for (const Link& link : solid.links) {
        const Element& r = h.elements()[link.receiver];
        if (!r.is_patch) continue;
        EXPECT_GT(
            glm::dot(h.patches()[r.patch].normal, h.elements()[link.sender].center - r.center),
            0.0f);
      }
    }
  }
}

// An object resting just above a floor (here a triangle 2 cm over a congruent one, facing it):
// Eq. 17's point model would give the floor's center a/d² ≈ 300 sr of the sender, two orders
// of magnitude beyond any irradiance (π L), and in a scene such pairs blow the iteration up.
// The link must deliver the exact cosine-weighted solid angle instead, as the passes compute
// it: L_in(b) = w_b F I_ex(j) with I_ex(j) = a |⟨n_k|ω_j⟩| L, E = ω_bin Σ_b ⟨n|−ω_b⟩₊ L_in(b).
TEST(AntiradianceLinking, ANearlyTouchingPairDeliversTheExactIrradianceNotThePointModel) {
  const float leg = 0.5f, gap = 0.02f;
  const Scene scene = build_scene(two_patches(leg, gap, /*lower_up=*/true, /*upper_up=*/false));
  const ElementHierarchy h(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(h.patch_count(), 2u);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  ASSERT_EQ(set.links.size(), 2u);
  expect_link_geometry(h, bins, set.links);
  for (const Link& link : set.links) {
    const Element& r = h.elements()[link.receiver];
    const Element& k = h.elements()[link.sender];
    const auto& to = h.patches()[r.patch];
    const auto& from = h.patches()[k.patch];
    const SpreadFilter filter = spreading.filter(link.spread_class, link.bin);
    double cosines = 0.0;
    for (size_t f = 0; f < filter.bins.size(); ++f) {
      cosines += filter.weights[f] *
                 std::max(0.0, -double(glm::dot(to.normal, bins.direction(filter.bins[f]))));
    }
    const double delivered = double(k.area) *
                             std::abs(double(glm::dot(from.normal, bins.direction(link.bin)))) *
                             link.form_factor * bins.solid_angle() * cosines;
    // 256² cells of 2 mm against a 20 mm gap: the midpoint rule is within 0.2%.
    const double exact = projected_solid_angle_by_quadrature(
        glm::dvec3(from.corners[0]), glm::dvec3(from.corners[1]), glm::dvec3(from.corners[2]),
        glm::dvec3(r.center), glm::dvec3(to.normal), 256);
    ASSERT_GT(exact, 0.5 * std::numbers::pi);  // the case where the bound applies
    EXPECT_NEAR(delivered, exact, 5e-3 * exact);
    EXPECT_LT(delivered, std::numbers::pi);
  }
}

TEST(AntiradianceLinking, LinksAreTheSameWhateverTheThreadCount) {
  const Scene scene = build_scene(closed_room());
  const ElementHierarchy h(scene, HierarchyOptions{0.4f, 0});
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet parallel = build_links(h, bins, spreading);
  LinkSet serial;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { serial = build_links(h, bins, spreading); });
  ASSERT_EQ(parallel.links.size(), serial.links.size());
  EXPECT_EQ(
      std::memcmp(parallel.links.data(), serial.links.data(), parallel.links.size() * sizeof(Link)),
      0);
  EXPECT_EQ(parallel.statistics.links_by_receiver_level, serial.statistics.links_by_receiver_level);
  uint64_t by_level = 0;
  for (uint64_t c : parallel.statistics.links_by_receiver_level) by_level += c;
  EXPECT_EQ(by_level, parallel.statistics.link_count);
}

TEST(AntiradianceLinking, RefusesMoreLinksThanTheBudget) {
  const Scene scene = build_scene(closed_room());
  const ElementHierarchy h(scene, HierarchyOptions{0.4f, 0});
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const uint64_t needed = build_links(h, bins, spreading).links.size();
  EXPECT_EQ(build_links(h, bins, spreading, LinkingOptions{needed, true}).links.size(), needed);
  try {
    build_links(h, bins, spreading, LinkingOptions{needed - 1, true});
    FAIL() << "a budget one link short was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
    EXPECT_NE(std::string(e.what()).find(std::to_string(needed - 1)), std::string::npos);
  }
}

TEST(AntiradianceLinking, StopsWhenCancelled) {
  const Scene scene = build_scene(closed_room());
  const ElementHierarchy h(scene, HierarchyOptions{0.4f, 0});
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  JobContext context;
  context.cancel();
  try {
    build_links(h, bins, spreading, {}, &context);
    FAIL() << "a cancelled job went on linking";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_CANCELLED);
  }
  JobContext running;
  running.set_stage("linking", 0.0, 1.0);
  EXPECT_FALSE(build_links(h, bins, spreading, {}, &running).links.empty());
  EXPECT_DOUBLE_EQ(running.progress(), 1.0);
}

TEST(AntiradianceLinking, RefusesSpreadingTablesOfOtherBins) {
  const Scene scene = build_scene(closed_room());
  const ElementHierarchy h(scene, HierarchyOptions{0.4f, 0});
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading other(DirectionalBins::from_bin_count(48));
  try {
    build_links(h, bins, other);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_ARGUMENT);
  }
}

// Not a check of results but of scale: link count and time on a Cornell-like box at the
// default patch size and 192 bins, printed for the benchmark table.
TEST(AntiradianceLinking, CornellBoxAtDefaultSettingsLinksEveryPatch) {
  const Scene scene = build_scene(cornell_like());
  const ElementHierarchy h(scene);
  const DirectionalBins bins = DirectionalBins::from_bin_count(192);
  const BinSpreading spreading(bins);
  const LinkSet set = build_links(h, bins, spreading);
  expect_link_geometry(
      h, bins,
      std::vector<Link>(set.links.begin(),
                        set.links.begin() + std::min<size_t>(set.links.size(), 100000)));
  // Every patch receives light, through its own links or its ancestors'.
  std::vector<uint8_t> receives(h.element_count(), 0);
  for (const Link& link : set.links) receives[link.receiver] = 1;
  for (size_t e = 1; e < h.element_count(); ++e) {
    if (receives[h.elements()[e].parent]) receives[e] = 1;
  }
  for (const auto& p : h.patches()) EXPECT_TRUE(receives[p.element]);
  std::printf(
      "cornell-like: %zu elements, %zu patches, %llu links (%.1f MiB), %.3f s, "
      "%llu wide patch links, %llu culled\n",
      h.element_count(), h.patch_count(),
      static_cast<unsigned long long>(set.statistics.link_count),
      set.statistics.memory_bytes / 1048576.0, set.statistics.seconds,
      static_cast<unsigned long long>(set.statistics.patch_pairs_kept_wide),
      static_cast<unsigned long long>(set.statistics.culled_behind_receiver));
  std::printf("links by receiver level:");
  for (uint64_t c : set.statistics.links_by_receiver_level) {
    std::printf(" %llu", static_cast<unsigned long long>(c));
  }
  std::printf("\n");
}

}  // namespace
}  // namespace bakegi::test
