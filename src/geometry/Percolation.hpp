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

// The same for any voxels marked open (non-zero), x fastest.
bool open_percolates(const std::array<long long, 3>& shape, int dimension, const std::vector<char>& open, int axis,
                     const std::array<bool, 3>& periodic);

// The width of the widest path through the pore along `axis` at its
// narrowest point: twice the largest distance t (from `distance`, the
// signed distance to the solid at the voxel centres) such that the voxels
// at least t from the solid still percolate. Measured between voxel
// centres, it is the bottleneck's width to within one voxel, from below
// (a gap of n voxels reads n when n is odd, n - 1 when even). 0 when the
// pore does not percolate.
double widest_path_width(const std::vector<double>& distance, const std::array<long long, 3>& shape, int dimension,
                         int axis, const std::array<bool, 3>& periodic);

}  // namespace poresph
