// Completing the coarse levels a query cannot see through the finer points it does see.
//
// Why: the coefficients are multilevel differences (Eq. 7 and Eq. 17 with the visible
// relations of visible_basis.h): a point j of level m carries α_j = f_j − Σ c_jk α_k over the
// coarser functions k that p_j sees, so the bulk of f_j lives in the coarse levels. A query
// (a gather ray's hit, Eq. 16, or a bake point) that sees some level m but none of a coarser
// level l's functions (all their centres behind a cushion's fold, a panel's edge, a plant's
// leaves) used to receive only level m's small differences: on the living room 8.9% of the
// transfer gather's hits saw no coarsest sender and lost most of the light they reflect;
// bake points on sofas whose coarse level was blocked came out about 30% low.
//
// The completion: when a query misses any level below the finest level m it sees, its row
// becomes that finest level's points j (weights b_j) with all of their coarser relations
// (k, b_j c_jk), the relations their coefficients were made the differences from. The levels
// 0..m then add up at the query to Σ_j b_j f_j, the Shepard mean of the projected values of
// the finest points it sees. Completing only the missing levels (through the nearest finer
// level seen) was tried first and is not consistent: where the finer points the query sees
// were blind to a coarse level too, their coefficients already hold that level's share, and
// adding it again made a bookshelf's inside 3x too bright (office). Nothing a seen point did
// not see is added: under a box standing on a lit floor, a point whose finer neighbours are
// also under the box gets their dark values, not the lit floor's coarse mean. A query that
// misses no level keeps its own row (every scene without such points is unchanged).
#pragma once

#include <vector>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/visible_basis.h"

namespace bakegi::meshless {

// `row` holds a query's visible weights (j, B^vis_j), any levels in any order, of points of
// `basis` (whose indices agree with those of `relations`' hierarchy for every coarser level).
// If a level below the finest one present has no entry, replaces the row as above and returns
// the number of such levels; otherwise leaves it and returns 0. No rays are cast.
uint32_t complete_missing_levels(const BasisHierarchy& basis, const VisibleRelations& relations,
                                 std::vector<BasisValue>& row);

}  // namespace bakegi::meshless
