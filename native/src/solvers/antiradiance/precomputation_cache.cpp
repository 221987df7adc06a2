#include "solvers/antiradiance/precomputation_cache.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "util/byte_stream.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

namespace {

constexpr uint32_t kStatistics = section_tag("STAT"), kHierarchy = section_tag("HIER"),
                   kElements = section_tag("ELEM"), kPatches = section_tag("PTCH"),
                   kMembers = section_tag("MEMB"), kLinks = section_tag("LINK");
// Bytes per record in the file (level and is_patch, subdivision level and back_side, bin,
// spread class and reserved share a u32).
constexpr size_t kElementBytes = 3 * 4 + 4 + 6 * 4 + 4 + 5 * 4 + 4;
constexpr size_t kPatchBytes = 9 * 4 + 4 * 3 * 4 + 4 + 3 * 4 + 4 + 3 * 4;
constexpr size_t kMemberBytes = 9 * 4 + 3 * 4;
constexpr size_t kLinkBytes = 3 * 4;  // the receiver is implied by the offsets
// The "bins" setting asks for at most 3072 bins, Nside 16: a larger Nside in a file is damage
// (and would build tables of gigabytes).
constexpr uint32_t kMaxNside = 16;

// The serializers below write every member; a member added to these types must be added
// here too (and kPrecomputationCacheVersion bumped), or the cache would drop it silently.
static_assert(sizeof(Element) == kElementBytes,
              "Element changed: update precomputation_cache.cpp and bump the cache version");
static_assert(sizeof(Patch) == kPatchBytes + 4,  // padding after the two narrow members
              "Patch changed: update precomputation_cache.cpp and bump the cache version");
static_assert(sizeof(MemberTriangle) == kMemberBytes,
              "MemberTriangle changed: update precomputation_cache.cpp and bump the version");
static_assert(sizeof(Link) == kLinkBytes + 4,
              "Link changed: update precomputation_cache.cpp and bump the cache version");
static_assert(sizeof(LinkingStatistics) == 2 * sizeof(std::vector<uint64_t>) + 6 * 8,
              "LinkingStatistics changed: update precomputation_cache.cpp and bump the version");
static_assert(sizeof(ElementHierarchy) == 3 * sizeof(std::vector<Element>) + 4 * 8,
              "ElementHierarchy changed: update precomputation_cache.cpp and bump the version");
static_assert(sizeof(GlobalPass) == 2 * sizeof(std::vector<Link>) + 2 * 8,
              "GlobalPass changed: update precomputation_cache.cpp and bump the cache version");
static_assert(sizeof(AntiradiancePrecomputation) ==
                  sizeof(Precomputation) + sizeof(DirectionalBins) + sizeof(BinSpreading) +
                      sizeof(ElementHierarchy) + sizeof(GlobalPass) + sizeof(LinkingStatistics) +
                      sizeof(std::vector<std::string>) + sizeof(double),
              "AntiradiancePrecomputation changed: update precomputation_cache.cpp and bump "
              "the cache version");

bool finite(float v) { return std::isfinite(v); }
bool finite(const glm::vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
bool non_negative(const glm::vec3& v) { return v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f; }
// Normals are normalized when made; a forged one would send rays from far away.
bool unit(const glm::vec3& v) { return std::abs(glm::dot(v, v) - 1.0f) < 1e-3f; }
// Room for rounding where the build computes a point inside bounds (centroids, means).
float slack(const Element& e) {
  const glm::vec3 far = glm::max(glm::abs(e.bounds_min), glm::abs(e.bounds_max));
  return 1e-3f * glm::length(e.bounds_max - e.bounds_min) +
         1e-5f * std::max({far.x, far.y, far.z}) + 1e-6f;
}
bool within(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
  return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
}

void write_u64s(ByteWriter& w, const std::vector<uint64_t>& values) {
  w.u64(values.size());
  for (uint64_t v : values) w.u64(v);
}

std::vector<uint64_t> read_u64s(ByteReader& r, const char* what) {
  std::vector<uint64_t> values;
  r.array(values, r.u64(), 8, what, [&] { return r.u64(); });
  return values;
}

void write_statistics(ByteWriter& w, const AntiradiancePrecomputation& p) {
  const size_t at = w.begin_section(kStatistics);
  w.u32(uint32_t(p.bins.nside()));
  w.f64(p.seconds);
  const LinkingStatistics& s = p.link_statistics;
  w.u64(s.link_count);
  write_u64s(w, s.links_by_receiver_level);
  write_u64s(w, s.links_by_sender_level);
  w.u64(s.patch_pairs_kept_wide);
  w.u64(s.culled_behind_receiver);
  w.u64(s.coincident_pairs);
  w.f64(s.seconds);
  w.u64(s.memory_bytes);
  w.u64(p.warnings.size());
  for (const std::string& warning : p.warnings) w.string(warning);
  w.end_section(at);
}

struct Statistics {
  uint32_t nside = 0;
  double seconds = 0.0;
  LinkingStatistics links;
  std::vector<std::string> warnings;
};

Statistics read_statistics(ByteReader& r) {
  Statistics s;
  s.nside = r.u32();
  if (s.nside < 1 || s.nside > kMaxNside) {
    r.fail("corrupt: Nside " + std::to_string(s.nside) + " is outside 1.." +
           std::to_string(kMaxNside));
  }
  s.seconds = r.f64();
  s.links.link_count = r.u64();
  s.links.links_by_receiver_level = read_u64s(r, "links by receiver level");
  s.links.links_by_sender_level = read_u64s(r, "links by sender level");
  s.links.patch_pairs_kept_wide = r.u64();
  s.links.culled_behind_receiver = r.u64();
  s.links.coincident_pairs = r.u64();
  s.links.seconds = r.f64();
  s.links.memory_bytes = r.u64();
  // A string is at least its u32 length.
  r.array(s.warnings, r.u64(), 4, "warnings", [&] { return r.string(); });
  return s;
}

}  // namespace

// Friend of ElementHierarchy and GlobalPass: reads and writes their members.
struct PrecomputationCacheAccess {
  static void write_hierarchy(ByteWriter& w, const ElementHierarchy& h) {
    size_t at = w.begin_section(kHierarchy);
    w.f32(h.max_edge_);
    w.u32(h.surface_count_);
    w.u64(h.merged_patch_count_);
    w.u64(h.back_side_count_);
    w.end_section(at);

    at = w.begin_section(kElements);
    w.u64(h.elements_.size());
    for (const Element& e : h.elements_) {
      w.vec3(e.center);
      w.f32(e.radius);
      w.vec3(e.bounds_min);
      w.vec3(e.bounds_max);
      w.f32(e.area);
      w.u32(e.parent);
      w.u32(e.first_child);
      w.u32(e.child_count);
      w.u32(e.subtree_end);
      w.u32(e.patch);
      w.u32(uint32_t(e.level) | uint32_t(e.is_patch) << 16);
    }
    w.end_section(at);

    at = w.begin_section(kPatches);
    w.u64(h.patches_.size());
    for (const Patch& p : h.patches_) {
      for (const glm::vec3& corner : p.corners) w.vec3(corner);
      w.vec3(p.normal);
      w.vec3(p.shading_normal);
      w.vec3(p.albedo);
      w.vec3(p.glossy);
      w.f32(p.glossy_exponent);
      w.u32(p.element);
      w.u32(p.triangle);
      w.u32(p.surface);
      w.u32(uint32_t(p.subdivision_level) | uint32_t(p.back_side) << 16);
      w.u32(p.sliver_piece);
      w.u32(p.first_member);
      w.u32(p.member_count);
    }
    w.end_section(at);

    at = w.begin_section(kMembers);
    w.u64(h.members_.size());
    for (const MemberTriangle& m : h.members_) {
      for (const glm::vec3& corner : m.corners) w.vec3(corner);
      w.u32(m.triangle);
      w.u32(m.code);
      w.f32(m.area);
    }
    w.end_section(at);
  }

  // The receivers' offsets (element count + 1 of them), then the links without their
  // receiver, which the offsets imply: a quarter less than the links in memory.
  static void write_transport(ByteWriter& w, const GlobalPass& pass) {
    const size_t at = w.begin_section(kLinks);
    w.u64(pass.element_count_);
    w.u64(pass.links_.size());
    // The links are most of the file: one allocation instead of a doubling series.
    w.bytes.reserve(w.bytes.size() + 4 * pass.receiver_offsets_.size() +
                    kLinkBytes * pass.links_.size() + 64);
    for (uint32_t offset : pass.receiver_offsets_) w.u32(offset);
    for (const Link& link : pass.links_) {
      w.u32(link.sender);
      w.u32(uint32_t(link.bin) | uint32_t(link.spread_class) << 16 |
            uint32_t(link.reserved) << 24);
      w.f32(link.form_factor);
    }
    w.end_section(at);
  }

  static void read_hierarchy(ByteReader& r, ElementHierarchy& h) {
    size_t end = r.open_section(kHierarchy, "hierarchy");
    h.max_edge_ = r.f32();
    h.surface_count_ = r.u32();
    const uint64_t merged = r.u64(), back_sides = r.u64();
    r.close_section(end, "hierarchy");

    end = r.open_section(kElements, "elements");
    r.array(h.elements_, r.u64(), kElementBytes, "elements", [&] {
      Element e;
      e.center = r.vec3();
      e.radius = r.f32();
      e.bounds_min = r.vec3();
      e.bounds_max = r.vec3();
      e.area = r.f32();
      e.parent = r.u32();
      e.first_child = r.u32();
      e.child_count = r.u32();
      e.subtree_end = r.u32();
      e.patch = r.u32();
      const uint32_t packed = r.u32();
      if (packed >> 17 != 0) r.fail("corrupt: an element's level or kind");
      e.level = uint16_t(packed & 0xffffu);
      e.is_patch = (packed >> 16) != 0;
      return e;
    });
    r.close_section(end, "elements");

    end = r.open_section(kPatches, "patches");
    r.array(h.patches_, r.u64(), kPatchBytes, "patches", [&] {
      Patch p;
      for (glm::vec3& corner : p.corners) corner = r.vec3();
      p.normal = r.vec3();
      p.shading_normal = r.vec3();
      p.albedo = r.vec3();
      p.glossy = r.vec3();
      p.glossy_exponent = r.f32();
      p.element = r.u32();
      p.triangle = r.u32();
      p.surface = r.u32();
      const uint32_t packed = r.u32();
      if (packed >> 17 != 0) r.fail("corrupt: a patch's subdivision level or side");
      p.subdivision_level = uint16_t(packed & 0xffffu);
      p.back_side = (packed >> 16) != 0;
      p.sliver_piece = r.u32();
      p.first_member = r.u32();
      p.member_count = r.u32();
      return p;
    });
    r.close_section(end, "patches");

    end = r.open_section(kMembers, "members");
    r.array(h.members_, r.u64(), kMemberBytes, "member triangles", [&] {
      MemberTriangle m;
      for (glm::vec3& corner : m.corners) corner = r.vec3();
      m.triangle = r.u32();
      m.code = r.u32();
      m.area = r.f32();
      return m;
    });
    r.close_section(end, "members");

    check_hierarchy(r, h, merged, back_sides);
    h.merged_patch_count_ = size_t(merged);
    h.back_side_count_ = size_t(back_sides);
  }

  // What the solver indexes with (push and pull walk the pre-order tree, the passes index
  // tables by element and patch) must be in range. Geometry must be what the build makes:
  // finite, an element's bounds exactly those of its corners or children (so every corner
  // lies within the root's), centres within the bounds, unit normals; rays from anything else
  // are invalid, and the output's grid would not end for non-finite centres. Triangle indices
  // and the root's bounds are checked against the scene by light(), which has it.
  static void check_hierarchy(ByteReader& r, const ElementHierarchy& h, uint64_t merged,
                              uint64_t back_sides) {
    const std::vector<Element>& elements = h.elements_;
    const std::vector<Patch>& patches = h.patches_;
    const size_t n = elements.size();
    if (!finite(h.max_edge_) || h.max_edge_ < 0.0f || (n > 0 && !(h.max_edge_ > 0.0f))) {
      r.fail("corrupt: the patch size");
    }
    // A binary tree with the patches as leaves.
    if (n != (patches.empty() ? 0 : 2 * patches.size() - 1) || n >= size_t(kNoElement)) {
      r.fail("corrupt: " + std::to_string(n) + " elements for " +
             std::to_string(patches.size()) + " patches");
    }
    if (n > 0 && (elements[0].parent != kNoElement || elements[0].level != 0 ||
                  elements[0].subtree_end != n)) {
      r.fail("corrupt: the root element");
    }
    // Every element is a child of its parent, which comes before it; a patch's subtree is
    // itself, a cluster's is itself and its two children's, which follow it in turn. By
    // induction every subtree is [i, subtree_end) and within the array.
    uint32_t next_patch = 0;
    for (size_t i = 0; i < n; ++i) {
      const Element& e = elements[i];
      if (!finite(e.center) || !finite(e.bounds_min) || !finite(e.bounds_max) ||
          !finite(e.radius) || !(e.radius >= 0.0f) || !finite(e.area) || !(e.area >= 0.0f)) {
        r.fail("corrupt: an element's geometry is not finite");
      }
      const float room = slack(e);
      if (!within(e.center, e.bounds_min - room, e.bounds_max + room) ||
          !(e.radius <= glm::length(e.bounds_max - e.bounds_min) + 2.0f * room)) {
        r.fail("corrupt: an element's centre or radius is outside its bounds");
      }
      if (e.subtree_end <= i || e.subtree_end > n) r.fail("corrupt: an element's subtree");
      if (i > 0) {
        if (e.parent >= i) r.fail("corrupt: an element's parent");
        const Element& parent = elements[e.parent];
        const bool first = parent.first_child == i;
        const bool second = !parent.is_patch && elements[parent.first_child].subtree_end == i;
        if (parent.is_patch || !(first || second) || e.level != parent.level + 1) {
          r.fail("corrupt: an element is not a child of its parent");
        }
      }
      if (e.is_patch) {
        if (e.child_count != 0 || e.first_child != kNoElement || e.subtree_end != i + 1 ||
            e.patch != next_patch || e.patch >= patches.size() ||
            patches[e.patch].element != i) {
          r.fail("corrupt: a patch element");
        }
        ++next_patch;
        continue;
      }
      if (e.child_count != 2 || e.first_child != i + 1 || e.patch != kNoElement ||
          i + 1 >= n) {
        r.fail("corrupt: a cluster element");
      }
      const uint32_t second = elements[i + 1].subtree_end;
      if (second >= e.subtree_end || elements[second].subtree_end != e.subtree_end ||
          elements[second].parent != i || elements[i + 1].parent != i) {
        r.fail("corrupt: a cluster's children");
      }
      const Element& a = elements[i + 1];
      const Element& b = elements[second];
      if (e.bounds_min != glm::min(a.bounds_min, b.bounds_min) ||
          e.bounds_max != glm::max(a.bounds_max, b.bounds_max)) {
        r.fail("corrupt: a cluster's bounds");
      }
    }
    if (next_patch != patches.size()) r.fail("corrupt: patches without elements");
    uint64_t merged_count = 0, back_count = 0;
    for (const Patch& p : patches) {
      for (const glm::vec3& corner : p.corners) {
        if (!finite(corner)) r.fail("corrupt: a patch corner is not finite");
      }
      if (!unit(p.normal) || !unit(p.shading_normal) || !finite(p.albedo) ||
          !non_negative(p.albedo) || !finite(p.glossy) || !non_negative(p.glossy) ||
          !finite(p.glossy_exponent) || !(p.glossy_exponent >= 0.0f)) {
        r.fail("corrupt: a patch's normal or material");
      }
      if (p.surface >= h.surface_count_) r.fail("corrupt: a patch's surface");
      if (p.subdivision_level > kMaxSubdivisionLevel) {
        r.fail("corrupt: a patch's subdivision level");
      }
      if (p.member_count > 0 &&
          uint64_t(p.first_member) + p.member_count > h.members_.size()) {
        r.fail("corrupt: a patch's member triangles");
      }
      // The element's bounds are exactly those of the corners (the members' for a merged
      // patch); the element was checked above, so p.element is in range.
      const Element& e = elements[p.element];
      glm::vec3 lo = p.member_count > 0 ? h.members_[p.first_member].corners[0] : p.corners[0];
      glm::vec3 hi = lo;
      const auto add = [&](const glm::vec3 (&corners)[3]) {
        for (const glm::vec3& corner : corners) {
          if (!finite(corner)) r.fail("corrupt: a corner is not finite");
          lo = glm::min(lo, corner);
          hi = glm::max(hi, corner);
        }
      };
      if (p.member_count == 0) {
        add(p.corners);
      } else {
        for (uint32_t m = p.first_member; m < p.first_member + p.member_count; ++m) {
          add(h.members_[m].corners);
        }
      }
      if (lo != e.bounds_min || hi != e.bounds_max) r.fail("corrupt: a patch's bounds");
      // A merged patch's corners are one of its members' (the one its centre lies on).
      if (!within(p.corners[0], lo, hi) || !within(p.corners[1], lo, hi) ||
          !within(p.corners[2], lo, hi)) {
        r.fail("corrupt: a patch's corners are outside its bounds");
      }
      merged_count += p.member_count > 0 ? 1 : 0;
      back_count += p.back_side ? 1 : 0;
    }
    if (merged_count != merged || back_count != back_sides) {
      r.fail("corrupt: the merged or back-side patch count");
    }
    for (const MemberTriangle& m : h.members_) {
      for (const glm::vec3& corner : m.corners) {
        if (!finite(corner)) r.fail("corrupt: a member triangle's corner is not finite");
      }
      if (!finite(m.area) || !(m.area >= 0.0f)) r.fail("corrupt: a member triangle's area");
    }
  }

  // The links as the global pass holds them: grouped by receiver (the receivers' offsets
  // follow from that), every index in range.
  static void read_transport(ByteReader& r, size_t element_count, const BinSpreading& spreading,
                             GlobalPass& pass) {
    const size_t end = r.open_section(kLinks, "links");
    const uint64_t elements = r.u64(), count = r.u64();
    if (elements != element_count) r.fail("corrupt: links for another hierarchy");
    if (count > UINT32_MAX) r.fail("corrupt: more than 2^32 links");
    if (element_count == 0) {
      if (count != 0) r.fail("corrupt: links without elements");
      r.close_section(end, "links");
      return;  // as precompute() leaves an empty scene's
    }
    std::vector<uint32_t> offsets;
    r.array(offsets, element_count + 1, 4, "receiver offsets", [&] { return r.u32(); });
    if (offsets.front() != 0 || offsets.back() != count) r.fail("corrupt: receiver offsets");
    for (size_t e = 0; e < element_count; ++e) {
      if (offsets[e + 1] < offsets[e]) r.fail("corrupt: receiver offsets decrease");
    }
    std::vector<Link> links;
    r.array(links, count, kLinkBytes, "links", [&] {
      Link link;
      link.sender = r.u32();
      const uint32_t packed = r.u32();
      link.bin = uint16_t(packed & 0xffffu);
      link.spread_class = uint8_t(packed >> 16);
      link.reserved = uint8_t(packed >> 24);
      link.form_factor = r.f32();
      return link;
    });
    r.close_section(end, "links");
    for (uint32_t receiver = 0; receiver < element_count; ++receiver) {
      for (uint32_t l = offsets[receiver]; l < offsets[receiver + 1]; ++l) {
        Link& link = links[l];
        link.receiver = receiver;
        if (link.sender >= element_count || int(link.bin) >= spreading.bin_count() ||
            int(link.spread_class) >= spreading.class_count()) {
          r.fail("corrupt: a link's sender, bin or spread class is out of range");
        }
        if (!finite(link.form_factor) || !(link.form_factor >= 0.0f)) {
          r.fail("corrupt: a link's form factor");
        }
      }
    }
    pass.links_ = std::move(links);
    pass.receiver_offsets_ = std::move(offsets);
    pass.element_count_ = element_count;
    pass.bin_count_ = spreading.bin_count();
  }
};

void encode_precomputation(const AntiradiancePrecomputation& precomputation, ByteWriter& w) {
  write_statistics(w, precomputation);
  PrecomputationCacheAccess::write_hierarchy(w, precomputation.hierarchy);
  PrecomputationCacheAccess::write_transport(w, precomputation.transport);
}

std::shared_ptr<AntiradiancePrecomputation> decode_precomputation(ByteReader& r,
                                                                  const JobContext* job) {
  const size_t end = r.open_section(kStatistics, "statistics");
  Statistics statistics = read_statistics(r);
  r.close_section(end, "statistics");

  // As precompute() makes them from the "bins" setting (from_bin_count picks this Nside).
  DirectionalBins bins(int(statistics.nside));
  BinSpreading spreading(bins);
  auto precomputation =
      std::make_shared<AntiradiancePrecomputation>(std::move(bins), std::move(spreading));
  if (job) job->throw_if_cancelled();

  PrecomputationCacheAccess::read_hierarchy(r, precomputation->hierarchy);
  PrecomputationCacheAccess::read_transport(r, precomputation->hierarchy.element_count(),
                                            precomputation->spreading,
                                            precomputation->transport);
  if (statistics.links.link_count != precomputation->transport.links().size()) {
    r.fail("corrupt: the statistics count " + std::to_string(statistics.links.link_count) +
           " links, the file holds " + std::to_string(precomputation->transport.links().size()));
  }
  precomputation->link_statistics = std::move(statistics.links);
  precomputation->warnings = std::move(statistics.warnings);
  precomputation->seconds = statistics.seconds;
  return precomputation;
}

}  // namespace bakegi::antiradiance
