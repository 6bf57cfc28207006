#pragma once
// Segmented images from files, through Debian's libpng and libtiff: the
// voxels and nothing else (which values are solid is the scene's business,
// Image/Solid Values). Axes as geometry/VoxelImage.hpp says: the first row
// of a PNG or TIFF page is at the largest y (y up, as the image is
// displayed), TIFF pages are z, and a raw volume is x fastest, then y, then z.
//
// Every reader throws std::invalid_argument naming the file and what is
// wrong with it (missing, truncated, colour, not the shape or type said)
// before anything else is done with the scene.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "geometry/VoxelImage.hpp"

namespace poresph {

// What a raw volume does not say about itself: its shape (2 values in 2D,
// 3 in 3D) and the bits of one value (8 or 16, little-endian).
struct RawLayout {
  std::vector<long long> shape;
  int bits = 8;
};

// Called with the number of voxels a file declares, and its shape ("nx x ny
// (x nz)"), once its header is read and before anything of that size is
// allocated: it throws to refuse an image too large for the memory. A
// header of a few hundred bytes can declare 10^10 voxels.
using ImageSizeCheck = std::function<void(long long voxels, const std::string& shape)>;

// 8 or 16-bit greyscale (1, 2 and 4 bits are read as 8, the values kept);
// refuses palette, colour and alpha images.
VoxelImage read_png(const std::string& path, const ImageSizeCheck& check = {});

// 8 or 16-bit greyscale unsigned samples, in strips or tiles; one page is a
// 2D image, several pages of one size a 3D stack, page p at z = p. Values
// are kept as stored, also where the file says 0 is white (a label is a
// label, however a viewer shades it).
VoxelImage read_tiff(const std::string& path, const ImageSizeCheck& check = {});

// Headerless values; the file's size must be exactly the layout's.
VoxelImage read_raw(const std::string& path, const RawLayout& layout, const ImageSizeCheck& check = {});

// Where an image's voxels are, with what a file does not say of itself.
struct ImageSource {
  std::string path;
  RawLayout raw;        // .raw only
  std::string dataset;  // .h5 and .hdf5 only: the dataset's path inside the file, e.g. "/segmented"
};

// What a file says of its image before any voxel is read.
struct ImageHeader {
  int dimension = 2;
  std::array<long long, 3> shape{{0, 0, 1}};  // nx, ny, nz as geometry/VoxelImage.hpp orders them
  int bits = 8;
};

// The voxels a reader keeps: along x, y and z the file's layer of each
// layer kept, in order. A box of the cell and its halo is a run of layers,
// wrapped around a periodic axis (..., n - 1, 0, 1, ...) and reflected
// along a mirrored one (..., n - 1, n - 1, n - 2, ...). An empty axis keeps
// every layer as stored.
struct ImageWindow {
  std::array<std::vector<long long>, 3> source;
};

// By the extension (any case): .png, .tif or .tiff, .raw (with `raw`).
VoxelImage read_image(const std::string& path, const RawLayout& raw, const ImageSizeCheck& check = {});
// The same, with .h5 and .hdf5 (with `dataset`).
VoxelImage read_image(const ImageSource& source, const ImageSizeCheck& check = {});

// The header alone: shape and bits, every page of a TIFF stack checked.
ImageHeader read_image_header(const ImageSource& source);

// The window's voxels and nothing else: a raw volume by seeks to its rows,
// a TIFF stack by its pages in the window, an HDF5 dataset by hyperslabs;
// a PNG (2D, and compressed as a whole) is decoded and cut. `check` is
// given the window's voxel count and the file's shape.
VoxelImage read_image_window(const ImageSource& source, const ImageWindow& window, const ImageSizeCheck& check = {});

// Integer datasets of 2 or 3 dimensions, stored [z][y][x] (x fastest, as
// h5py writes a numpy array a[z, y, x] and as a raw volume lies), without
// a flip. Unsigned 8-bit values keep 8 bits; any other integer type is
// read as 16 bits, and a value outside 0 .. 65535 is refused.
VoxelImage read_hdf5(const std::string& path, const std::string& dataset, const ImageSizeCheck& check = {});

// The window cut from an image already held (x, y, z layers of `image`).
VoxelImage take_window(const VoxelImage& image, const ImageWindow& window);

}  // namespace poresph
