#pragma once
// Distances in a voxel image: the exact Euclidean distance transform and
// the signed distance to the solid built on it, the image's counterpart of
// a grain's |x - c| - r. Not used by the solver yet (issue 16).
#include <array>
#include <vector>

#include "geometry/VoxelImage.hpp"

namespace poresph {

// The squared distance, in voxels squared, from every voxel centre to the
// nearest centre of a voxel where `site` is non-zero (0 on a site; infinity
// when there is none). Exact, with the separable algorithm of Felzenszwalb
// & Huttenlocher ("Distance transforms of sampled functions", Theory of
// Computing 8, 2012): the lower envelope of parabolas along x, then along
// y of that, then along z, linear in the voxels. Along a periodic axis the
// nearest site may lie across the cell's face.
std::vector<double> squared_distance_transform(const std::array<long long, 3>& shape, int dimension,
                                               const std::array<bool, 3>& periodic, const std::vector<char>& site);

// Signed distance (m) from each voxel centre to the solid, positive in the
// pore and negative in the solid: the distance to the nearest centre of the
// other phase less half a voxel, so that the surface lies halfway between
// unlike neighbours (exact across a face; the staircase of the voxels is
// not smoothed away here). Solid voxels are those whose value is listed.
std::vector<double> signed_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic);

}  // namespace poresph
