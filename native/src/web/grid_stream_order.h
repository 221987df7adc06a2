// The order in which a grid's vertices are streamed (Pacanowski et al. 2008, §4.1): first
// its eight corners, then coarse to fine, each level (the vertices on a lattice of stride
// 2^l that no coarser level sent) stratified as in the paper: the grid is cut into slices
// along its longest axis and the level's vertices leave each slice in random order, taking
// the slices in turn, so that any request of a fixed number of vectors spreads over the
// whole grid. A client fills the vertices it lacks by push-pull (grid/grid_push_pull.h).
#pragma once

#include <cstdint>
#include <vector>

#include "grid/grid_layout.h"

namespace bakegi {

// Every vertex index of `layout` once, in stream order; the same for the same seed.
std::vector<uint32_t> grid_stream_order(const GridLayout& layout, uint64_t seed = 1);

}  // namespace bakegi
