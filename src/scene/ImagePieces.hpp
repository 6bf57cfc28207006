#pragma once
// A segmented image held in pieces: each process reads the voxels of its
// box of the cell and a halo around it (io/ImageReader.hpp reads just those),
// and makes its walls and checks from them. The halo is what makes a piece's
// walls those of the whole image: the distance field at a voxel depends on
// the surface near it only, so a piece whose halo reaches past every surface
// point its box's walls use gives the same values, bit for bit (a piece
// computes its surface points and distances in the whole image's
// coordinates, geometry/DistanceTransform.hpp). Percolation is not local: each process labels the pore of
// its box, and the labels are joined across the boxes' faces on one process.
#include <array>
#include <string>
#include <vector>

#include "geometry/VoxelImage.hpp"
#include "io/ImageReader.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {

// The voxels whose centres lie in the box [lo, hi) (m), as a lattice
// point's does: the boxes of a decomposition share the voxels out, each to
// one. A lattice point in the box reads the voxels up to one beyond them,
// which the halo covers.
VoxelBox voxel_box(const double* lo, const double* hi, int dimension, double voxel_size,
                   const std::array<long long, 3>& cell_voxels);

// How an image's voxels lie in the cell: its shape in the file, and
// Image/Mirror's axis (-1: none), which doubles the cell along it.
struct ImageLayout {
  int dimension = 2;
  std::array<long long, 3> file_shape{{0, 0, 1}};
  int mirror_axis = -1;
  std::array<bool, 3> periodic{{true, true, true}};  // the cell's
  std::array<long long, 3> cell_voxels() const {
    std::array<long long, 3> n = file_shape;
    if (mirror_axis >= 0) n[mirror_axis] *= 2;
    return n;
  }
};

// One process's piece: the voxels of its box and of the halo around it.
struct ImagePiece {
  VoxelImage voxels;                    // x fastest, the halo included
  std::array<long long, 3> first{};     // the cell's voxel of voxels' voxel 0 (unwrapped: below 0 across a face)
  std::array<bool, 3> wraps{};          // the piece is the whole of this periodic axis, and wraps as the cell does
  VoxelBox box;                         // the box itself, in the cell's voxels
  std::array<long long, 3> cell{};      // the cell's voxels
  std::array<bool, 3> periodic{};       // the cell's periodic axes
  int dimension = 2;

  // The piece's voxel of the cell's voxel c (unwrapped as `first` is).
  long long index_of_cell_voxel(const std::array<long long, 3>& c) const;
};

// Which layers of the file a piece of `box` and `halo` voxels reads: the box
// widened by the halo, wrapped around periodic axes, cut at the bounded
// ones' ends, reflected in the mirrored half. An axis the box spans whole
// is read whole, without a halo.
ImageWindow piece_window(const ImageLayout& layout, const VoxelBox& box, long long halo, ImagePiece& piece);

// The piece, read from the file: only its window's voxels.
ImagePiece read_image_piece(const ImageSource& source, const ImageLayout& layout, const VoxelBox& box,
                            long long halo, const ImageSizeCheck& check = {});

// The same piece cut from the whole image held in memory (tests, and the
// yardstick the pieces are compared with).
ImagePiece cut_image_piece(const VoxelImage& cell_image, const ImageLayout& layout, const VoxelBox& box,
                           long long halo);

// The halo (voxels) a piece needs for the walls of lattice points in its
// box, at a boundary layer `shell` (m) deep: the distance is read at most
// DistanceField::kNormalStep + 1 voxels from a point, and there must be
// exact to the shell's depth plus that reach; a surface point depends on
// the voxels within 4 of it (blur, gradient, crossing).
long long walls_halo(double shell, double voxel_size);

// The largest distance (m) a piece with `halo` voxels holds exactly at
// every voxel of its box; beyond it, a value may differ from the whole
// image's (the nearest surface can lie outside the piece).
double piece_trusted_distance(long long halo, double voxel_size);

// The signed distance to the surface (geometry/DistanceTransform.hpp) over
// the piece: the whole image's values wherever the nearest surface lies
// within the halo less the reach above.
std::vector<float> piece_surface_distance(const ImagePiece& piece, const std::vector<int>& solid_values,
                                          double voxel_size);

// Whether the voxels marked open in the piece's box (one flag a voxel of
// the piece, halo ignored), joined across faces and across the boxes of
// all processes, hold a path through the cell along `axis`, as
// open_percolates (geometry/Percolation.hpp) finds on the whole image.
// Collective over comm.
bool pieces_percolate(const ImagePiece& piece, const std::vector<char>& open, int axis,
                      const std::array<bool, 3>& periodic, const Communicator& comm);

// widest_path_width over the pieces (collective): twice the largest
// distance t for which the voxels at least t from the solid percolate.
// Distances above `trusted` (m) are taken as `trusted`, as beyond what the
// halo makes exact: a width of 2 trusted or more reads as 2 trusted.
double pieces_widest_path_width(const ImagePiece& piece, const std::vector<float>& distance, int axis,
                                const std::array<bool, 3>& periodic, double trusted, const Communicator& comm);

}  // namespace poresph
