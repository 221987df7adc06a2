// Link refinement of Antiradiance (paper §3.2, with the form factor of Eq. 17 and the solid
// assumption of Fig. 7): from the root's self-link, links are refined until each sender covers
// at most one directional bin as seen from its receiver, or until both ends are patches.
//
// Rules, for a pair receiver i ← sender k:
// - i == k (a self-link) is always replaced by the links between all ordered pairs of i's
//   children, each child's self-link included; a patch's self-link produces nothing.
// - i != k: the oracle compares the solid angle of the sender seen from the receiver, ω_k,
//   and (LinkingOptions::test_receiver, the default) symmetrically ω_i (a big receiver sees
//   the sender in different bins from its different parts) with oracle_factor · ω_bin,
//   ω_bin = 4π/m. By default ω = π r² / d² with r the element's bounding radius and d the
//   distance of the centers: the solid angle of the disk of the bounding sphere's radius
//   facing the viewer (exact for a far sphere, an upper bound of a flat patch's, and defined
//   for clusters, which have no normal). OracleExtent::kProjectedArea uses the projected area
//   instead (fewer links, a little more error: docs/methods/antiradiance.md). If either exceeds the
//   bound, the element with the larger radius that is not a patch is subdivided (the sender
//   on a tie) and its children are linked recursively. When both are patches, the link is
//   kept as it is (the discretization threshold of §3.2) and carries the spreading class of
//   its sender's cone (Fig. 8).
// - A kept link gets bin = bin_of(x_i − x_k) (the direction light travels, see link.h) and
//   form factor 1 / (d² ω_bin) (Eq. 17), except for patch pairs so close that the point model
//   would deliver more than π/2 of cosine-weighted solid angle (objects resting on others:
//   it can exceed π, any possible irradiance, by orders of magnitude, and the iteration blows
//   up): their form factor is lowered so that the link delivers, through the cosines the
//   passes apply, max(exact, π/2), with "exact" the cosine-weighted solid angle of the sender
//   triangle from the receiver's center (Lambert's contour formula). Pairs farther apart than
//   twice their radii never reach the bound.
// - Solids only (Fig. 7): a link to a PATCH receiver is dropped when the sender's center lies
//   on or behind the receiver's plane (⟨n_i | x_k − x_i⟩ ≤ 0): light arriving at the back of a
//   solid's surface is never received. A patch sender sends into both hemispheres (radiance in
//   front, antiradiance behind), so the sender's side is not tested; clusters have no normal
//   and never cull. Patches facing each other get links both ways; a patch facing away from
//   another sends to it but receives nothing from it.
// - Two patches whose centers coincide (d ≤ 1e-6 (r_i + r_k)) exchange nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/link.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::antiradiance {

// How the oracle measures the solid angle an element subtends from a point at distance d.
enum class OracleExtent {
  // π r²/d² with the bounding radius r: the disk of the bounding sphere facing the viewer
  // (exact for a far sphere; for a flat triangle ~2.4× its area even face-on).
  kBoundingSphere,
  // The projected area over d²: a |⟨n|ω⟩| / d² for a patch (its solid angle when far), and
  // min(π r², a) / d² for a cluster, whose summed area bounds its projected area and which
  // has no normal.
  kProjectedArea,
};

struct LinkingOptions {
  // Refuse with Error(OUT_OF_MEMORY) as soon as more links than this would be kept; 0 leaves
  // only the limit of the address space. 16 bytes per link (link.h).
  uint64_t max_links = 0;
  // The Fig. 7 culling at patch receivers; off only to test the hierarchy's coverage.
  bool cull_behind_receiver = true;
  // The oracle: a pair is refined while the sender (and, with test_receiver, the receiver)
  // subtends more than oracle_factor · ω_bin as seen from the other end. Factor 1 is the
  // paper's "larger than the solid angle of a bin".
  double oracle_factor = 1.0;
  bool test_receiver = true;
  OracleExtent extent = OracleExtent::kBoundingSphere;
};

struct LinkingStatistics {
  uint64_t link_count = 0;
  // Kept links by the level (depth below the root) of their receiver and of their sender.
  std::vector<uint64_t> links_by_receiver_level;
  std::vector<uint64_t> links_by_sender_level;
  uint64_t patch_pairs_kept_wide = 0;   // patch-patch links whose sender covers more than a bin
  uint64_t culled_behind_receiver = 0;  // pairs dropped by the Fig. 7 test
  uint64_t coincident_pairs = 0;        // patch pairs dropped for coinciding centers
  double seconds = 0.0;
  uint64_t memory_bytes = 0;  // of the link array
};

struct LinkSet {
  std::vector<Link> links;
  LinkingStatistics statistics;
};

// Builds the links of `hierarchy` for `bins`. The result is deterministic: the links come in
// the depth-first order of the refinement, whatever the number of threads (the top of the
// refinement is cut into tasks that run in parallel on the current TBB arena and whose outputs
// are concatenated in order). Checks `context` (optional) for cancellation and reports the
// fraction of tasks done as stage progress. Throws Error(OUT_OF_MEMORY) when more than
// options.max_links links would be kept, Error(CANCELLED) when cancelled, and
// Error(INVALID_ARGUMENT) when `spreading` was built for other bins.
LinkSet build_links(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                    const BinSpreading& spreading, const LinkingOptions& options = {},
                    JobContext* context = nullptr);

}  // namespace bakegi::antiradiance
