// An image held in pieces against the same image held whole, on 1, 2 and 4
// ranks, in 2D and 3D, periodic and mirrored: each rank reads its box and
// halo from the file (raw, HDF5), and its voxels, its distance field where
// the walls read it, its lattice's fluid and boundary particles, and the
// percolation and bottleneck found over all pieces are the whole image's.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/Kernel.hpp"
#include "geometry/DistanceTransform.hpp"
#include "geometry/Lattice.hpp"
#include "geometry/Percolation.hpp"
#include "io/ImageReader.hpp"
#include "parallel/Communicator.hpp"
#include "scene/ImagePieces.hpp"

namespace poresph {
namespace {

namespace fs = std::filesystem;

// Overlapping balls (disks) of radius 2.5 to 6 voxels, wrapped around the
// periodic cell, from a fixed linear congruential sequence: solid 1, pore 0.
VoxelImage balls(int dimension, const std::array<long long, 3>& shape, int count, unsigned seed) {
  VoxelImage image;
  image.dimension = dimension;
  image.shape = shape;
  image.values.assign(static_cast<size_t>(image.count()), 0);
  std::uint64_t state = seed;
  auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int b = 0; b < count; ++b) {
    double centre[3] = {0, 0, 0};
    for (int d = 0; d < dimension; ++d) centre[d] = uniform() * static_cast<double>(shape[d]);
    const double radius = 2.5 + 3.5 * uniform();
    for (long long k = 0; k < shape[2]; ++k)
      for (long long j = 0; j < shape[1]; ++j)
        for (long long i = 0; i < shape[0]; ++i) {
          const long long at[3] = {i, j, k};
          double r_sq = 0;
          for (int d = 0; d < dimension; ++d) {
            double r = at[d] + 0.5 - centre[d];
            r -= shape[d] * std::round(r / shape[d]);
            r_sq += r * r;
          }
          if (r_sq < radius * radius) image.values[image.index(i, j, k)] = 1;
        }
  }
  return image;
}

void write_raw(const std::string& path, const VoxelImage& image) {
  std::ofstream out(path, std::ios::binary);
  for (std::uint16_t v : image.values) out.put(static_cast<char>(v));
}

// [z][y][x] (or [y][x]) as int32, a type the raw and TIFF readers do not take.
void write_hdf5(const std::string& path, const VoxelImage& image) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hid_t group = H5Gcreate2(file, "/scan", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hsize_t dims[3];
  for (int d = 0; d < image.dimension; ++d) dims[d] = static_cast<hsize_t>(image.shape[image.dimension - 1 - d]);
  const hid_t space = H5Screate_simple(image.dimension, dims, nullptr);
  const hid_t set = H5Dcreate2(file, "/scan/segmented", H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  std::vector<std::int32_t> values(image.values.begin(), image.values.end());
  H5Dwrite(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(set);
  H5Sclose(space);
  H5Gclose(group);
  H5Fclose(file);
}

// A folder all ranks share, made by rank 0 and removed by it at the end.
struct SharedFolder {
  fs::path path;
  Communicator comm;
  SharedFolder() {
    long long id = comm.rank() == 0 ? static_cast<long long>(getpid()) : 0;
    id = comm.sum(id);
    path = fs::temp_directory_path() / ("poresph-pieces-" + std::to_string(id));
    if (comm.rank() == 0) fs::create_directories(path);
    MPI_Barrier(comm.comm());
  }
  ~SharedFolder() {
    MPI_Barrier(comm.comm());
    std::error_code ignored;
    if (comm.rank() == 0) fs::remove_all(path, ignored);
  }
};

// This rank's box of a process grid over the cell: x split at 40 % for two
// ranks, x and y for four (unequal parts, so that no box is another's image).
template <int Dim>
void rank_box(int rank, int ranks, const std::array<double, 3>& cell, double (&lo)[Dim], double (&hi)[Dim]) {
  for (int d = 0; d < Dim; ++d) lo[d] = 0, hi[d] = cell[d];
  auto split = [&](int d, int part) {
    const double cut = std::round(0.4 * cell[d] * 1e6) / 1e6;
    lo[d] = part == 0 ? 0.0 : cut;
    hi[d] = part == 0 ? cut : cell[d];
  };
  if (ranks >= 2) split(0, rank % 2);
  if (ranks >= 4) split(1, rank / 2);
}

struct Case {
  int dimension;
  std::array<long long, 3> shape;
  int balls;
  int mirror_axis;
  double spacing_per_voxel;  // particle spacing over voxel size
  std::string format;        // "raw" or "h5"
};

std::string describe(const Case& c) {
  return std::to_string(c.dimension) + "D " + c.format + (c.mirror_axis >= 0 ? ", mirrored" : ", periodic") +
         ", dx = " + std::to_string(c.spacing_per_voxel) + " voxel";
}

template <int Dim>
void compare_pieces_with_whole(const Case& c) {
  SCOPED_TRACE(describe(c));
  const Communicator comm;
  const SharedFolder folder;
  const double voxel = 1e-3;
  const VoxelImage file_image = balls(c.dimension, c.shape, c.balls, 7u + static_cast<unsigned>(c.dimension));
  const std::string path = (folder.path / ("image." + c.format)).string();
  if (comm.rank() == 0) c.format == "raw" ? write_raw(path, file_image) : write_hdf5(path, file_image);
  MPI_Barrier(comm.comm());
  ImageSource source;
  source.path = path;
  if (c.format == "raw") source.raw = RawLayout{std::vector<long long>(c.shape.begin(), c.shape.begin() + Dim), 8};
  else source.dataset = "/scan/segmented";

  ImageLayout layout;
  layout.dimension = Dim;
  layout.file_shape = c.shape;
  layout.mirror_axis = c.mirror_axis;
  const VoxelImage whole = c.mirror_axis >= 0 ? mirrored(file_image, c.mirror_axis) : file_image;
  const std::vector<int> solid_values{1};

  SceneConfig scene;
  scene.dimension = Dim;
  for (int d = 0; d < Dim; ++d) scene.cell_size[d] = static_cast<double>(whole.shape[d]) * voxel;
  scene.particle_spacing = voxel * c.spacing_per_voxel;
  scene.image.solid_values = solid_values;
  scene.image.voxel_size = voxel;
  scene.image.voxels = std::make_shared<const VoxelImage>(whole);
  scene.image.distance =
      std::make_shared<const std::vector<float>>(surface_distance(whole, solid_values, voxel, scene.periodic));

  double lo[Dim], hi[Dim];
  rank_box<Dim>(comm.rank(), comm.size(), scene.cell_size, lo, hi);
  const VoxelBox box = voxel_box(lo, hi, Dim, voxel, whole.shape);
  const double shell = kSupportRadiusInH * scene.smoothing_length_ratio * scene.particle_spacing;
  const long long halo = walls_halo(shell, voxel);

  // The voxels: read from the file as cut from the whole image.
  const ImagePiece piece = read_image_piece(source, layout, box, halo);
  const ImagePiece cut = cut_image_piece(whole, layout, box, halo);
  ASSERT_EQ(piece.voxels.shape, cut.voxels.shape);
  EXPECT_EQ(piece.voxels.values, cut.voxels.values);
  EXPECT_EQ(piece.first, cut.first);
  for (int d = 0; d < Dim; ++d) {
    const bool split = (d == 0 && comm.size() >= 2) || (d == 1 && comm.size() >= 4);
    EXPECT_EQ(piece.wraps[d], !split) << "axis " << d;  // a whole periodic axis wraps, without a halo
  }

  // The distance field wherever the walls read it: the box, the reach of a
  // lattice point's reads around it, at depths up to the shell and that reach.
  const auto distance = piece_surface_distance(piece, solid_values, voxel);
  const long long reach = 6;
  const double band = shell + reach * voxel;
  long long compared = 0, differing = 0;
  std::array<long long, 3> at{};
  std::array<long long, 3> from{{0, 0, 0}}, to{{1, 1, 1}};
  for (int d = 0; d < Dim; ++d) from[d] = box.lo[d] - reach, to[d] = box.hi[d] + reach;
  for (at[2] = from[2]; at[2] < to[2]; ++at[2])
    for (at[1] = from[1]; at[1] < to[1]; ++at[1])
      for (at[0] = from[0]; at[0] < to[0]; ++at[0]) {
        std::array<long long, 3> cell_at = at;
        for (int d = 0; d < 3; ++d) cell_at[d] = (at[d] % whole.shape[d] + whole.shape[d]) % whole.shape[d];
        const float expected = (*scene.image.distance)[whole.index(cell_at[0], cell_at[1], cell_at[2])];
        if (!(std::abs(expected) <= band)) continue;
        ++compared;
        differing += distance[static_cast<size_t>(piece.index_of_cell_voxel(at))] != expected;
      }
  EXPECT_GT(compared, 100);
  EXPECT_EQ(differing, 0) << "of " << compared << " voxels within " << band / voxel << " voxels of the surface";

  // The particles of this rank's box: the same fluid and boundary particles, bit for bit.
  SceneConfig in_pieces = scene;
  in_pieces.image.voxels = std::make_shared<const VoxelImage>(piece.voxels);
  in_pieces.image.distance = std::make_shared<const std::vector<float>>(distance);
  in_pieces.image.piece_first = piece.first;
  in_pieces.image.piece_wraps = piece.wraps;
  in_pieces.image.owned = piece.box;
  const auto expected_seeds = fill_lattice<Dim>(scene, lo, hi);
  const auto seeds = fill_lattice<Dim>(in_pieces, lo, hi);
  ASSERT_EQ(seeds.size(), expected_seeds.size());
  long long boundary = 0, seed_differences = 0;
  for (size_t p = 0; p < seeds.size(); ++p) {
    boundary += seeds[p].kind == kSampledBoundary;
    seed_differences += seeds[p].id != expected_seeds[p].id || seeds[p].kind != expected_seeds[p].kind ||
                        seeds[p].wall_scalar != expected_seeds[p].wall_scalar ||
                        std::memcmp(seeds[p].wall_vector, expected_seeds[p].wall_vector,
                                    sizeof seeds[p].wall_vector) != 0;
  }
  EXPECT_GT(comm.sum(boundary), 0);
  EXPECT_EQ(seed_differences, 0) << "of " << seeds.size() << " particles";

  // The share of pore narrower than three spacings, counted box by box.
  const double narrow = 3 * scene.particle_spacing;
  EXPECT_EQ(pore_fraction_narrower_than(in_pieces, narrow), pore_fraction_narrower_than(scene, narrow));

  // Percolation and the widest path's bottleneck over all pieces, along
  // each axis, periodic and bounded along it.
  const std::vector<double> whole_widths(scene.image.distance->begin(), scene.image.distance->end());
  const double trusted = piece_trusted_distance(halo, voxel);
  for (int axis = 0; axis < Dim; ++axis)
    for (bool bounded : {false, true}) {
      SCOPED_TRACE("axis " + std::to_string(axis) + (bounded ? ", bounded" : ", periodic"));
      std::array<bool, 3> periodic{{true, true, true}};
      periodic[axis] = !bounded;
      for (double level : {0.0, 2.0 * voxel, 4.0 * voxel}) {
        std::vector<char> whole_open(whole_widths.size()), piece_open(distance.size());
        for (size_t n = 0; n < whole_open.size(); ++n) whole_open[n] = whole_widths[n] > level;
        for (size_t n = 0; n < piece_open.size(); ++n) piece_open[n] = distance[n] > level;
        EXPECT_EQ(pieces_percolate(piece, piece_open, axis, periodic, comm),
                  open_percolates(whole.shape, Dim, whole_open, axis, periodic))
            << "open beyond " << level / voxel << " voxels";
      }
      const double expected = std::min(widest_path_width(whole_widths, whole.shape, Dim, axis, periodic),
                                       2.0 * static_cast<double>(static_cast<float>(trusted)));
      EXPECT_GT(expected, 0);
      EXPECT_EQ(pieces_widest_path_width(piece, distance, axis, periodic, trusted, comm), expected);
    }
}

TEST(ImagePieces, VolumeOfBallsRawPeriodic) { compare_pieces_with_whole<3>({3, {{44, 36, 30}}, 34, -1, 1.0, "raw"}); }
TEST(ImagePieces, VolumeOfBallsHdf5Mirrored) { compare_pieces_with_whole<3>({3, {{24, 36, 30}}, 20, 0, 1.0, "h5"}); }
TEST(ImagePieces, PlaneOfDisksHdf5PeriodicHalfVoxelSpacing) {
  compare_pieces_with_whole<2>({2, {{96, 84, 1}}, 40, -1, 0.5, "h5"});
}
TEST(ImagePieces, PlaneOfDisksRawMirrored) { compare_pieces_with_whole<2>({2, {{60, 84, 1}}, 30, 0, 1.0, "raw"}); }

}  // namespace
}  // namespace poresph
