#include "solvers/antiradiance/link_refinement.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

namespace {

// Patch pairs closer than this fraction of their radii are coincident (overlapping coplanar
// triangles): their form factor would be unbounded and their bin meaningless.
constexpr double kCoincidentFraction = 1e-6;
// A sender within this angle (radians, as a cosine offset) of a patch receiver's plane is
// coplanar with it: float rounding must not decide whether coplanar patches exchange light.
constexpr double kCoplanarCosine = 1e-5;
// The cosine-weighted solid angle (sr) below which the point model of Eq. 17 is trusted for a
// patch pair (Refiner::near_field_scale).
constexpr double kNearFieldBound = 0.5 * std::numbers::pi;
// Links a task keeps before it adds them to the shared count and checks the budget: bounds
// the overshoot of max_links to this many per thread, and keeps the atomic off the hot path.
constexpr uint64_t kBudgetFlushLinks = 4096;
// Refinement steps between two cancellation checks.
constexpr uint64_t kCancelCheckSteps = 4096;
// The top of the refinement is expanded into at least this many tasks per thread, so that
// uneven subtrees still balance across threads.
constexpr size_t kTasksPerThread = 64;

// The cosine-weighted solid angle ∫ ⟨n|ω⟩ dω of the triangle `corners` seen from x with unit
// normal n (π times the point-to-triangle form factor), of the part in front of x's plane:
// Lambert's contour formula, Σ_edges γ_e ⟨n|u_e⟩ / 2 with γ_e the angle an edge subtends and
// u_e the unit normal of the plane through x and the edge, after clipping the triangle at the
// plane (at most a quadrilateral remains).
double projected_solid_angle(const glm::vec3 (&corners)[3], const glm::dvec3& x,
                             const glm::dvec3& n) {
  glm::dvec3 clipped[4];
  int count = 0;
  for (int c = 0; c < 3; ++c) {
    const glm::dvec3 a = glm::dvec3(corners[c]) - x, b = glm::dvec3(corners[(c + 1) % 3]) - x;
    const double ha = glm::dot(n, a), hb = glm::dot(n, b);
    if (ha > 0.0) clipped[count++] = a;
    if ((ha > 0.0) != (hb > 0.0)) clipped[count++] = a + (ha / (ha - hb)) * (b - a);
  }
  double sum = 0.0;
  for (int e = 0; e < count; ++e) {
    const glm::dvec3& a = clipped[e];
    const glm::dvec3& b = clipped[(e + 1) % count];
    const glm::dvec3 u = glm::cross(a, b);
    const double length = glm::length(u);
    if (!(length > 0.0)) continue;
    sum += std::atan2(length, glm::dot(a, b)) * glm::dot(n, u) / length;
  }
  return 0.5 * std::abs(sum);
}

struct Pair {
  uint32_t receiver;
  uint32_t sender;
};

enum class Decision { kSelfLink, kSplitReceiver, kSplitSender, kKeep, kCulled, kCoincident };

// Everything one refinement step decides about a pair, and what a kept link needs.
struct Verdict {
  Decision decision;
  double distance = 0.0;
  double sender_solid_angle = 0.0;
};

class Refiner {
 public:
  Refiner(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
          const BinSpreading& spreading, const LinkingOptions& options)
      : elements_(hierarchy.elements()),
        patches_(hierarchy.patches()),
        members_(hierarchy.members_all()),
        bins_(bins),
        spreading_(spreading),
        options_(options),
        bin_solid_angle_(bins.solid_angle()),
        threshold_(options.oracle_factor * bins.solid_angle()) {}

  // A pure function of the pair: the task expansion and the tasks both call it.
  Verdict decide(Pair pair) const {
    const Element& receiver = elements_[pair.receiver];
    const Element& sender = elements_[pair.sender];
    if (pair.receiver == pair.sender) return {Decision::kSelfLink};

    const glm::dvec3 x_i(receiver.center), x_k(sender.center);
    const glm::dvec3 to_sender = x_k - x_i;
    // Nothing of the sender's subtree lies in front of a patch receiver's plane: whatever the
    // refinement below would keep is culled, so stop here (the box holds every descendant's
    // center, so this agrees with the test on kept links).
    if (options_.cull_behind_receiver && receiver.is_patch) {
      const glm::dvec3 n(patches_[receiver.patch].normal);
      const glm::dvec3 box_center =
          0.5 * (glm::dvec3(sender.bounds_min) + glm::dvec3(sender.bounds_max));
      const glm::dvec3 half_extent =
          0.5 * (glm::dvec3(sender.bounds_max) - glm::dvec3(sender.bounds_min));
      const double farthest_in_front =
          glm::dot(n, box_center - x_i) + glm::dot(glm::abs(n), half_extent);
      if (farthest_in_front <= 0.0) return {Decision::kCulled};
    }

    const double d2 = glm::dot(to_sender, to_sender);
    const double r_i = receiver.radius, r_k = sender.radius;
    const double distance = std::sqrt(d2);
    const bool coincident = !(distance > kCoincidentFraction * (r_i + r_k));
    const glm::dvec3 direction = coincident ? glm::dvec3(0.0) : to_sender / distance;
    const double sender_solid_angle =
        coincident ? std::numeric_limits<double>::infinity() : solid_angle(sender, direction, d2);
    const double receiver_solid_angle =
        coincident ? std::numeric_limits<double>::infinity()
                   : (options_.test_receiver ? solid_angle(receiver, direction, d2) : 0.0);

    if (std::max(sender_solid_angle, receiver_solid_angle) > threshold_) {
      const bool can_split_receiver = !receiver.is_patch, can_split_sender = !sender.is_patch;
      if (can_split_sender && (r_k >= r_i || !can_split_receiver)) {
        return {Decision::kSplitSender};
      }
      if (can_split_receiver) return {Decision::kSplitReceiver};
      if (coincident) return {Decision::kCoincident};
    }

    if (options_.cull_behind_receiver && receiver.is_patch) {
      const glm::dvec3 n(patches_[receiver.patch].normal);
      if (glm::dot(n, to_sender) <= kCoplanarCosine * distance) return {Decision::kCulled};
    }
    return {Decision::kKeep, distance, sender_solid_angle};
  }

  // The solid angle `e` subtends from a point at squared distance d2 along ±direction (the
  // measure of options_.extent; the sign of the direction does not matter).
  double solid_angle(const Element& e, const glm::dvec3& direction, double d2) const {
    const double r = e.radius;
    const double sphere = std::numbers::pi * r * r;
    if (options_.extent == OracleExtent::kBoundingSphere) return sphere / d2;
    if (e.is_patch) {
      const glm::dvec3 n(patches_[e.patch].normal);
      return double(e.area) * std::abs(glm::dot(n, direction)) / d2;
    }
    return std::min(sphere, double(e.area)) / d2;
  }

  // Calls visit(child_pair) for the pairs a split pair is replaced by, in refinement order.
  template <class Visit>
  void for_each_child_pair(Pair pair, Decision decision, Visit&& visit) const {
    auto for_each_child = [this](uint32_t parent, auto&& f) {
      const Element& e = elements_[parent];
      uint32_t child = e.first_child;
      for (uint32_t c = 0; c < e.child_count; ++c) {
        f(child);
        child = elements_[child].subtree_end;
      }
    };
    switch (decision) {
      case Decision::kSelfLink:
        for_each_child(pair.receiver, [&](uint32_t a) {
          for_each_child(pair.receiver, [&](uint32_t b) { visit(Pair{a, b}); });
        });
        break;
      case Decision::kSplitReceiver:
        for_each_child(pair.receiver, [&](uint32_t c) { visit(Pair{c, pair.sender}); });
        break;
      case Decision::kSplitSender:
        for_each_child(pair.sender, [&](uint32_t c) { visit(Pair{pair.receiver, c}); });
        break;
      default:
        break;
    }
  }

  Link make_link(Pair pair, const Verdict& verdict) const {
    const glm::dvec3 travel =
        glm::dvec3(elements_[pair.receiver].center) - glm::dvec3(elements_[pair.sender].center);
    Link link;
    link.receiver = pair.receiver;
    link.sender = pair.sender;
    link.bin = static_cast<uint16_t>(bins_.bin_of(travel));
    link.spread_class = static_cast<uint8_t>(spreading_.class_of(verdict.sender_solid_angle));
    link.form_factor = static_cast<float>(near_field_scale(pair, link, verdict.distance) /
                                          (verdict.distance * verdict.distance * bin_solid_angle_));
    return link;
  }

  // Eq. 17 treats the sender as a point: the receiver's irradiance from it is
  // a_k |⟨n_k|ω⟩| ⟨n_i|−ω⟩ L / d². For two patches close together (an object resting on
  // another: d of a millimetre, patches of centimetres) that exceeds any possible irradiance
  // (π L) by orders of magnitude and the iteration explodes. Between patches, the form factor
  // is therefore scaled so that the irradiance the link delivers (through the sender's
  // cosine at the central bin and the receiver's cosines over the spread bins, as the passes
  // compute it) equals the exact cosine-weighted solid angle of the sender triangle seen from
  // the receiver's center times L. Far pairs keep Eq. 17 (the ratio tends to 1). Both ways:
  // the exact values of a closed room's patches add up to π at every receiver, so a furnace
  // keeps its energy, while the point model loses the part of a wide spread that falls below
  // a neighbour's horizon (4% per bounce in the closed-box test). Raised by at most
  // kMaxNearFieldGain, for senders nearly edge-on at the central bin.
  double near_field_scale(Pair pair, const Link& link, double distance) const {
    const Element& receiver = elements_[pair.receiver];
    const Element& sender = elements_[pair.sender];
    if (!receiver.is_patch || !sender.is_patch) return 1.0;
    const Patch& to = patches_[receiver.patch];
    const Patch& from = patches_[sender.patch];
    const glm::dvec3 n_i(to.normal);
    const glm::dvec3 central(bins_.direction(link.bin));
    double delivered_cosine = 0.0;  // Σ_b w_b ⟨n_i|−ω_b⟩₊ over the spread
    const SpreadFilter filter = spreading_.filter(link.spread_class, link.bin);
    for (size_t f = 0; f < filter.bins.size(); ++f) {
      delivered_cosine +=
          double(filter.weights[f]) *
          std::max(0.0, -glm::dot(n_i, glm::dvec3(bins_.direction(filter.bins[f]))));
    }
    const double point_model = double(sender.area) *
                               std::abs(glm::dot(glm::dvec3(from.normal), central)) *
                               delivered_cosine / (distance * distance);
    // max(exact, bound) / point_model >= 1 whenever the point model is within the bound:
    // only pairs beyond it need the exact value (a merged sender sums it over its members).
    if (!(point_model > kNearFieldBound)) return 1.0;
    const glm::dvec3 x(receiver.center);
    double exact = 0.0;
    if (from.member_count == 0) {
      exact = projected_solid_angle(from.corners, x, n_i);
    } else {
      for (const MemberTriangle& member : members_.subspan(from.first_member, from.member_count)) {
        exact += projected_solid_angle(member.corners, x, n_i);
      }
    }
    return std::min(1.0, std::max(exact, kNearFieldBound) / point_model);
  }

  double bin_solid_angle() const { return bin_solid_angle_; }
  const std::vector<Element>& elements() const { return elements_; }

 private:
  const std::vector<Element>& elements_;
  const std::vector<Patch>& patches_;
  std::span<const MemberTriangle> members_;
  const DirectionalBins& bins_;
  const BinSpreading& spreading_;
  const LinkingOptions& options_;
  double bin_solid_angle_;
  double threshold_;  // the oracle's bound on the solid angles
};

// What one task produced.
struct TaskOutput {
  std::vector<Link> links;
  std::vector<uint64_t> by_receiver_level, by_sender_level;
  uint64_t wide = 0, culled = 0, coincident = 0;
};

[[noreturn]] void refuse_budget(uint64_t max_links, const ElementHierarchy& hierarchy,
                                const DirectionalBins& bins) {
  std::ostringstream message;
  message << "antiradiance: linking needs more than " << max_links << " links ("
          << (max_links * sizeof(Link) >> 20) << " MiB) for " << hierarchy.element_count()
          << " elements at " << bins.bin_count()
          << " bins; raise the link budget, use fewer bins, or coarsen the patches (a larger "
             "patch size)";
  throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, message.str());
}

}  // namespace

LinkSet build_links(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                    const BinSpreading& spreading, const LinkingOptions& options,
                    JobContext* context) {
  const auto start = std::chrono::steady_clock::now();
  if (!(options.oracle_factor > 0.0) || !std::isfinite(options.oracle_factor)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "antiradiance: the linking oracle factor must be positive and finite");
  }
  if (spreading.bin_count() != bins.bin_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "antiradiance: the spreading tables were built for other directional bins");
  }
  if (context) context->throw_if_cancelled();

  LinkSet result;
  const auto& elements = hierarchy.elements();
  uint16_t max_level = 0;
  for (const Element& e : elements) max_level = std::max(max_level, e.level);
  result.statistics.links_by_receiver_level.assign(size_t(max_level) + 1, 0);
  result.statistics.links_by_sender_level.assign(size_t(max_level) + 1, 0);
  if (elements.empty()) return result;

  const Refiner refiner(hierarchy, bins, spreading, options);
  const uint64_t max_links =
      options.max_links ? options.max_links : std::numeric_limits<uint64_t>::max();

  // Expand the top of the refinement in place (split pairs replaced by their children, in
  // order) until there are enough tasks; the concatenation of the tasks' depth-first outputs
  // is then exactly the serial depth-first order.
  const size_t wanted_tasks =
      kTasksPerThread * size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  std::vector<Pair> tasks{Pair{0, 0}};
  for (bool split = true; split && tasks.size() < wanted_tasks;) {
    split = false;
    std::vector<Pair> next;
    next.reserve(tasks.size() * 4);
    for (const Pair pair : tasks) {
      const Decision decision = refiner.decide(pair).decision;
      if (decision == Decision::kSelfLink || decision == Decision::kSplitReceiver ||
          decision == Decision::kSplitSender) {
        refiner.for_each_child_pair(pair, decision, [&](Pair child) { next.push_back(child); });
        split = true;
      } else {
        next.push_back(pair);
      }
    }
    tasks = std::move(next);
  }

  std::vector<TaskOutput> outputs(tasks.size());
  std::atomic<uint64_t> links_counted{0};
  std::atomic<size_t> tasks_done{0};

  auto run_task = [&](size_t task_index) {
    TaskOutput& out = outputs[task_index];
    out.by_receiver_level.assign(size_t(max_level) + 1, 0);
    out.by_sender_level.assign(size_t(max_level) + 1, 0);
    uint64_t unflushed = 0, steps = 0;
    std::vector<Pair> stack{tasks[task_index]};
    std::vector<Pair> children;
    while (!stack.empty()) {
      const Pair pair = stack.back();
      stack.pop_back();
      if (context && ++steps % kCancelCheckSteps == 0) context->throw_if_cancelled();
      const Verdict verdict = refiner.decide(pair);
      switch (verdict.decision) {
        case Decision::kKeep: {
          out.links.push_back(refiner.make_link(pair, verdict));
          ++out.by_receiver_level[elements[pair.receiver].level];
          ++out.by_sender_level[elements[pair.sender].level];
          if (verdict.sender_solid_angle > refiner.bin_solid_angle()) ++out.wide;
          if (++unflushed == kBudgetFlushLinks || out.links.size() > max_links) {
            const uint64_t total = links_counted.fetch_add(unflushed) + unflushed;
            unflushed = 0;
            if (total > max_links) refuse_budget(max_links, hierarchy, bins);
          }
          break;
        }
        case Decision::kCulled:
          ++out.culled;
          break;
        case Decision::kCoincident:
          ++out.coincident;
          break;
        default:
          // Children go on the stack in reverse so that they pop in refinement order.
          children.clear();
          refiner.for_each_child_pair(pair, verdict.decision,
                                      [&](Pair child) { children.push_back(child); });
          stack.insert(stack.end(), children.rbegin(), children.rend());
          break;
      }
    }
    const uint64_t total = links_counted.fetch_add(unflushed) + unflushed;
    if (total > max_links) refuse_budget(max_links, hierarchy, bins);
    const size_t done = tasks_done.fetch_add(1) + 1;
    if (context) context->set_stage_progress(double(done) / double(tasks.size()));
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tasks.size(), 1),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t t = range.begin(); t != range.end(); ++t) run_task(t);
                    });
  if (context) context->throw_if_cancelled();

  LinkingStatistics& stats = result.statistics;
  uint64_t total = 0;
  for (const TaskOutput& out : outputs) total += out.links.size();
  result.links.reserve(total);
  for (TaskOutput& out : outputs) {
    result.links.insert(result.links.end(), out.links.begin(), out.links.end());
    std::vector<Link>().swap(out.links);
    for (size_t l = 0; l <= max_level; ++l) {
      stats.links_by_receiver_level[l] += out.by_receiver_level[l];
      stats.links_by_sender_level[l] += out.by_sender_level[l];
    }
    stats.patch_pairs_kept_wide += out.wide;
    stats.culled_behind_receiver += out.culled;
    stats.coincident_pairs += out.coincident;
  }
  stats.link_count = result.links.size();
  stats.memory_bytes = result.links.capacity() * sizeof(Link);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace bakegi::antiradiance
