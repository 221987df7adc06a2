// Filling the grid's invalid vertices (Pacanowski et al. 2008, §4.1, Fig. 2): a 3D push-pull.
// Push: each coarser level (half the vertices per axis, rounded up) averages the valid
// vertices of the finer one under a pyramid (tent) filter, weights carried along, so every
// level is smooth ("a pyramidal filter after each push step"). Pull: from the coarsest level
// down, each invalid vertex takes the trilinear interpolation of the level above it. Valid
// vertices are never changed ("our push-pull algorithm does not modify any received data").
// The same fill runs at bake time (vertices inside geometry) and in the streaming client
// (vertices not yet received; addon/web mirrors this file).
#pragma once

#include "grid/irradiance_vector_grid.h"

namespace bakegi {

// Fills grid's invalid vertices in place (its vectors and its emitted light); returns how many it
// filled. With no valid vertex at all, the grid stays as it is (all zero) and 0 is returned.
size_t fill_invalid_vertices(IrradianceVectorGrid& grid);

}  // namespace bakegi
