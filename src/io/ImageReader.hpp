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

// By the extension (any case): .png, .tif or .tiff, .raw (with `raw`).
VoxelImage read_image(const std::string& path, const RawLayout& raw, const ImageSizeCheck& check = {});

}  // namespace poresph
