// Maintenance of the hierarchy (§3.2, §4.2).
//
// push: after the global pass, the radiance gathered at a cluster applies to every point under
//   it. Radiance is intensive, so each descendant receives its ancestors' L_in unchanged, added
//   to what its own links brought. In pre-order the parent comes first, so one forward pass
//   adding the parent's (already complete) row to each element's row does it.
// pull: after the local pass, a cluster's exitant intensity is the sum of its children's
//   (intensity is flux per solid angle and adds up); a backward pass sets each cluster's I_ex
//   row to that sum, children before parents.
//
// Both split the tree into the few elements near the root and disjoint subtrees below them,
// walked in parallel; every row is computed by the same sequence of operations whatever the
// thread count, so results are bit-identical.
#pragma once

#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

// L_in(e) += L_in(parent(e)) for every element in pre-order. Throws Error(INVALID_ARGUMENT)
// when the tables do not have a row per element. `context` (optional) is checked for cancel
// every kElementsPerCancelCheck elements: a sweep of the tables at many bins takes tens of
// milliseconds.
void push(const ElementHierarchy& hierarchy, RadianceTables& tables,
          const JobContext* context = nullptr);

// I_ex(c) = Σ_children I_ex(child) for every cluster, leaves first. Throws
// Error(INVALID_ARGUMENT) when the tables do not have a row per element. `context` as push's.
void pull(const ElementHierarchy& hierarchy, RadianceTables& tables,
          const JobContext* context = nullptr);

}  // namespace bakegi::antiradiance
