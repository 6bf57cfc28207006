#pragma once
// Distances in a voxel image: the exact Euclidean distance transform and
// the signed distance to the solid built on it, the image's counterpart of
// a grain's |x - c| - r.
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
// With `nearest`, also the flat index of the site each voxel is nearest to
// (-1 where there is none): the feature transform.
std::vector<double> squared_distance_transform(const std::array<long long, 3>& shape, int dimension,
                                               const std::array<bool, 3>& periodic, const std::vector<char>& site,
                                               std::vector<long long>* nearest = nullptr);

// Signed distance (m) from each voxel centre to the solid, positive in the
// pore and negative in the solid: the distance to the nearest centre of the
// other phase less half a voxel, so that the surface lies halfway between
// unlike neighbours (exact across a face; the staircase of the voxels is
// not smoothed away here). Solid voxels are those whose value is listed.
std::vector<double> signed_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic);

// A signed distance as above, smoothed at the voxel scale: each voxel's
// value averaged with its neighbours' by the weights 1/4, 1/2, 1/4 along
// every axis in turn, so that the staircase of the voxels does not become
// the wall the fluid sees. A distance that changes linearly (a plane
// surface) is kept exactly; a curved one moves by a small fraction of a
// voxel. Stored as float: a solver reads it at every boundary particle and
// grid node, and a volume of 512^3 voxels takes 0.5 GB.
std::vector<float> smoothed_at_voxel_scale(std::vector<double> distance, const std::array<long long, 3>& shape,
                                           int dimension, const std::array<bool, 3>& periodic);

// The signed distance (m) the walls are built from, positive in the pore:
// the distance to a surface found between the voxels, not on their
// staircase. The pore indicator is blurred (1/4, 1/2, 1/4 along each axis,
// twice); each voxel next to where it crosses 1/2 steps from its centre to
// that level (one Newton step along the gradient), giving a point of the
// surface and its normal; every voxel then takes the distance to the
// tangent plane of the surface point nearest it (found through the feature
// transform of the surface voxels and the points around the one found).
// A voxel centre's distance to the staircase less half a voxel is exact
// for a face between voxels but reads a curved surface about a quarter of
// a voxel too far out (a disk of 54 voxels: -0.17 to -0.27 voxel on
// average at the fluid particles next to it), which moved k by 1 to 3 %.
//
// With `frame`, the image is a piece of a larger one (scene/ImagePieces.hpp),
// and the surface points and distances are computed in the whole image's
// coordinates: where the piece holds a voxel's surface, its distance is the
// whole image's to the bit.
struct VoxelFrame {
  std::array<long long, 3> first{};  // the cell's voxel of the piece's voxel 0 (unwrapped)
  std::array<long long, 3> shape{};  // the cell's voxels
  std::array<bool, 3> periodic{};    // the cell's periodic axes
};
std::vector<float> surface_distance(const VoxelImage& image, const std::vector<int>& solid_values, double voxel_size,
                                    const std::array<bool, 3>& periodic, const VoxelFrame* frame = nullptr);

}  // namespace poresph
