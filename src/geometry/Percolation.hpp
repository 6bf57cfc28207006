#pragma once
// Whether a voxel image's pore space carries flow along an axis at all: an
// image whose pores do not connect across the cell has k = 0 and a run of
// it would only say so after all its steps.
#include <array>
#include <vector>

#include "geometry/VoxelImage.hpp"

namespace poresph {

// True when the pore voxels (those whose value is not listed as solid),
// joined across faces only (two voxels meeting at an edge or a corner leave
// no gap a particle lattice could fill), hold a path along `axis`. Along a
// periodic axis that is a path from a voxel to its own image one cell
// further, so a pore region that reaches both faces but is closed in the
// middle does not count; along a bounded axis, a path from face to face.
// Periodic axes other than `axis` are crossed freely.
bool pore_percolates(const VoxelImage& image, const std::vector<int>& solid_values, int axis,
                     const std::array<bool, 3>& periodic);

}  // namespace poresph
