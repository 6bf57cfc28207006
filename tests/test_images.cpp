// Segmented images: each format read with the axes docs/method.md states,
// every bad image refused with its reason, and the Image parameters checked
// against the rest of the scene. The files are written here with libpng and
// libtiff themselves, so that a reader and a writer agree on what a file is
// only through the format.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <png.h>
#include <tiffio.h>

#include <Teuchos_Array.hpp>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/SceneCheck.hpp"
#include "geometry/Percolation.hpp"
#include "geometry/VoxelImage.hpp"
#include "io/ImageReader.hpp"
#include "io/Parameters.hpp"
#include "scene/SceneBuilder.hpp"
#include "ErrorOf.hpp"
#include "MinimalScene.hpp"
#include "VoxelSketch.hpp"

namespace poresph {
namespace {

using testing::error_of;

namespace fs = std::filesystem;
using Teuchos::Array;
using Teuchos::ParameterList;

// The files of this process, in a folder of its own (builds of other
// branches may run this test at the same time), removed at exit.
std::string temp_path(const std::string& name) {
  static const struct Folder {
    fs::path path = fs::temp_directory_path() / ("poresph-images-" + std::to_string(getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } folder;
  return (folder.path / name).string();
}

// Rows top first, as both formats store them; values one per sample.
struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned> values;  // width * height * samples, row-major from the top row
};

// libpng's writer longjmps here on an error; no object with a destructor lives in this frame.
bool png_write_all(png_structp png, png_infop info, std::FILE* file, int width, int height, int depth, int colour,
                   bool interlaced, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, depth, colour, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (colour == PNG_COLOR_TYPE_PALETTE) {
    png_color palette[2] = {{0, 0, 0}, {255, 0, 0}};
    png_set_PLTE(png, info, palette, 2);
  }
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

// A PNG of `depth` bits a sample (packed as the format packs 1, 2 and 4 bits, big-endian at 16).
void write_png(const std::string& path, const Picture& picture, int depth, int colour = PNG_COLOR_TYPE_GRAY,
               bool interlaced = false) {
  const int samples = colour == PNG_COLOR_TYPE_RGB ? 3 : colour == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : 1;
  const size_t row_bytes = (static_cast<size_t>(picture.width) * samples * depth + 7) / 8;
  std::vector<png_byte> bytes(row_bytes * picture.height, 0);
  for (int r = 0; r < picture.height; ++r)
    for (int s = 0; s < picture.width * samples; ++s) {
      const unsigned v = picture.values[static_cast<size_t>(r) * picture.width * samples + s];
      png_byte* row = bytes.data() + r * row_bytes;
      if (depth == 16) {
        row[2 * s] = static_cast<png_byte>(v >> 8);
        row[2 * s + 1] = static_cast<png_byte>(v & 0xff);
      } else if (depth == 8) {
        row[s] = static_cast<png_byte>(v);
      } else {  // the first pixel in the most significant bits
        const int per_byte = 8 / depth;
        row[s / per_byte] |= static_cast<png_byte>(v << (8 - depth * (s % per_byte + 1)));
      }
    }
  std::vector<png_bytep> rows(picture.height);
  for (int r = 0; r < picture.height; ++r) rows[r] = bytes.data() + r * row_bytes;
  std::FILE* file = std::fopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr) << path;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  const bool written =
      png_write_all(png, info, file, picture.width, picture.height, depth, colour, interlaced, rows.data());
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
  ASSERT_TRUE(written) << path;
}

struct TiffPage {
  Picture picture;
  int bits = 8, samples = 1;
  int photometric = PHOTOMETRIC_MINISBLACK, format = SAMPLEFORMAT_UINT;
  int tile = 0;  // tile side (a multiple of 16), 0: strips
  int compression = COMPRESSION_NONE;
};

// One page a TiffPage, in the host's byte order (libtiff marks it in the header).
void write_tiff(const std::string& path, const std::vector<TiffPage>& pages) {
  TIFF* tiff = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tiff, nullptr) << path;
  for (const auto& page : pages) {
    const int w = page.picture.width, h = page.picture.height, n = page.samples, bytes_per = page.bits / 8;
    TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, w);
    TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, h);
    TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, page.bits);
    TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, n);
    TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, page.photometric);
    TIFFSetField(tiff, TIFFTAG_SAMPLEFORMAT, page.format);
    TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tiff, TIFFTAG_COMPRESSION, page.compression);
    if (pages.size() > 1) {
      TIFFSetField(tiff, TIFFTAG_SUBFILETYPE, FILETYPE_PAGE);
    }
    auto sample_bytes = [&](int r, int x0, int count, unsigned char* out) {
      for (int s = 0; s < count * n; ++s) {
        const unsigned v = page.picture.values[(static_cast<size_t>(r) * w + x0) * n + s];
        if (page.format == SAMPLEFORMAT_IEEEFP) {
          const float f = static_cast<float>(v);
          std::memcpy(out + 4 * s, &f, 4);
        } else if (bytes_per == 2) {
          const std::uint16_t u = static_cast<std::uint16_t>(v);
          std::memcpy(out + 2 * s, &u, 2);
        } else {
          out[s] = static_cast<unsigned char>(v);
        }
      }
    };
    if (page.tile > 0) {
      TIFFSetField(tiff, TIFFTAG_TILEWIDTH, page.tile);
      TIFFSetField(tiff, TIFFTAG_TILELENGTH, page.tile);
      std::vector<unsigned char> tile(static_cast<size_t>(page.tile) * page.tile * n * bytes_per);
      for (int y0 = 0; y0 < h; y0 += page.tile)
        for (int x0 = 0; x0 < w; x0 += page.tile) {
          std::fill(tile.begin(), tile.end(), 0);
          for (int r = y0; r < std::min(h, y0 + page.tile); ++r)
            sample_bytes(r, x0, std::min(page.tile, w - x0),
                         tile.data() + static_cast<size_t>(r - y0) * page.tile * n * bytes_per);
          ASSERT_GE(TIFFWriteTile(tiff, tile.data(), x0, y0, 0, 0), 0);
        }
    } else {
      TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, 2);  // several strips a page
      std::vector<unsigned char> row(static_cast<size_t>(w) * n * bytes_per);
      for (int r = 0; r < h; ++r) {
        sample_bytes(r, 0, w, row.data());
        ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), r, 0), 1);
      }
    }
    ASSERT_TRUE(TIFFWriteDirectory(tiff));
  }
  TIFFClose(tiff);
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

// The file cut to `keep` bytes.
void truncate_to(const std::string& path, std::uintmax_t keep) {
  ASSERT_GT(fs::file_size(path), keep);
  fs::resize_file(path, keep);
}

#define EXPECT_MENTIONS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

// Three wide, two high, every value different: a flip or a transposition
// of either axis moves some value.
Picture asymmetric(unsigned scale = 1) {
  return {3, 2, {1 * scale, 2 * scale, 3 * scale, 4 * scale, 5 * scale, 6 * scale}};
}

// The top row of the picture (1 2 3) is at y = 1, the largest; x to the right.
void expect_asymmetric_axes(const VoxelImage& image, unsigned scale = 1) {
  ASSERT_EQ(image.dimension, 2);
  ASSERT_EQ(image.shape[0], 3);
  ASSERT_EQ(image.shape[1], 2);
  ASSERT_EQ(image.shape[2], 1);
  ASSERT_EQ(image.values.size(), 6u);
  EXPECT_EQ(image.at(0, 1), 1 * scale);
  EXPECT_EQ(image.at(1, 1), 2 * scale);
  EXPECT_EQ(image.at(2, 1), 3 * scale);
  EXPECT_EQ(image.at(0, 0), 4 * scale);
  EXPECT_EQ(image.at(2, 0), 6 * scale);
}

TEST(ImageReader, PngRowsAreReadTopRowAtTheLargestY) {
  const auto path = temp_path("axes.png");
  write_png(path, asymmetric(), 8);
  const auto image = read_png(path);
  expect_asymmetric_axes(image);
  EXPECT_EQ(image.bits, 8);
}

TEST(ImageReader, Png16BitKeepsEveryBit) {
  // 258 = 0x0102 and 513 = 0x0201: a byte-order slip swaps them.
  const auto path = temp_path("16.png");
  write_png(path, {3, 2, {258, 513, 65535, 0, 1, 40000}}, 16);
  const auto image = read_png(path);
  EXPECT_EQ(image.bits, 16);
  EXPECT_EQ(image.at(0, 1), 258);
  EXPECT_EQ(image.at(1, 1), 513);
  EXPECT_EQ(image.at(2, 1), 65535);
  EXPECT_EQ(image.at(2, 0), 40000);
  // Interlaced (Adam7) the same pixels arrive in seven passes.
  const auto interlaced = temp_path("16-adam7.png");
  write_png(interlaced, {3, 2, {258, 513, 65535, 0, 1, 40000}}, 16, PNG_COLOR_TYPE_GRAY, true);
  EXPECT_EQ(read_png(interlaced).values, image.values);
}

TEST(ImageReader, PngOfFewBitsKeepsItsValues) {
  // A binary segmentation saved as 1 bit: values 0 and 1, not 0 and 255.
  Picture picture{10, 3, {}};
  for (int k = 0; k < 30; ++k) picture.values.push_back(k % 3 == 0 ? 1 : 0);
  const auto path = temp_path("1bit.png");
  write_png(path, picture, 1);
  const auto image = read_png(path);
  EXPECT_EQ(image.bits, 8);
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i < 10; ++i) EXPECT_EQ(image.at(i, 2 - r), picture.values[r * 10 + i]) << i << " " << r;
}

TEST(ImageReader, ColourPngsAreRefusedSayingWhy) {
  const auto rgb = temp_path("rgb.png");
  write_png(rgb, {1, 1, {10, 20, 30}}, 8, PNG_COLOR_TYPE_RGB);
  const auto rgb_error = error_of([&] { read_png(rgb); });
  EXPECT_MENTIONS(rgb_error, "colour");
  EXPECT_MENTIONS(rgb_error, "greyscale");
  EXPECT_MENTIONS(rgb_error, rgb);
  const auto palette = temp_path("palette.png");
  write_png(palette, {2, 1, {0, 1}}, 8, PNG_COLOR_TYPE_PALETTE);
  EXPECT_MENTIONS(error_of([&] { read_png(palette); }), "palette");
  const auto alpha = temp_path("alpha.png");
  write_png(alpha, {1, 1, {10, 255}}, 8, PNG_COLOR_TYPE_GRAY_ALPHA);
  EXPECT_MENTIONS(error_of([&] { read_png(alpha); }), "alpha");
}

TEST(ImageReader, BrokenPngsAreRefused) {
  Picture big{64, 64, std::vector<unsigned>(64 * 64)};
  for (size_t k = 0; k < big.values.size(); ++k) big.values[k] = (k * 7919) % 251;  // compresses badly
  const auto path = temp_path("truncated.png");
  write_png(path, big, 8);
  truncate_to(path, fs::file_size(path) / 2);
  EXPECT_MENTIONS(error_of([&] { read_png(path); }), "truncated");
  // Cut inside the header: no pixel was reached.
  write_png(path, big, 8);
  truncate_to(path, 20);
  EXPECT_MENTIONS(error_of([&] { read_png(path); }), "unreadable");
  const auto text = temp_path("text.png");
  std::ofstream(text) << "not a picture\n";
  EXPECT_MENTIONS(error_of([&] { read_png(text); }), "not a PNG");
  EXPECT_MENTIONS(error_of([&] { read_png(temp_path("missing.png")); }), "no such file");
  EXPECT_MENTIONS(error_of([&] { read_png(fs::temp_directory_path().string()); }), "directory");
}

TEST(ImageReader, TiffPageHasThePngAxes) {
  const auto path = temp_path("axes.tif");
  TiffPage page;
  page.picture = asymmetric();
  write_tiff(path, {page});
  const auto image = read_tiff(path);
  expect_asymmetric_axes(image);
  EXPECT_EQ(image.bits, 8);
  // Shaded with 0 as white, the labels are the same labels.
  page.photometric = PHOTOMETRIC_MINISWHITE;
  const auto white = temp_path("min-is-white.tif");
  write_tiff(white, {page});
  expect_asymmetric_axes(read_tiff(white));
}

TEST(ImageReader, TiffStackIsAVolumeWithPagesAlongZ) {
  // Page p holds 1000 p + 10 r + i at row r (from the top), column i, in 16 bits.
  const int nx = 5, ny = 3, nz = 4;
  std::vector<TiffPage> pages(nz);
  for (int p = 0; p < nz; ++p) {
    pages[p].bits = 16;
    pages[p].picture = {nx, ny, {}};
    for (int r = 0; r < ny; ++r)
      for (int i = 0; i < nx; ++i) pages[p].picture.values.push_back(1000 * p + 10 * r + i);
  }
  pages[1].compression = COMPRESSION_LZW;  // a page compressed, as Fiji may write it
  const auto path = temp_path("stack.tiff");
  write_tiff(path, pages);
  const auto image = read_tiff(path);
  ASSERT_EQ(image.dimension, 3);
  ASSERT_EQ(image.shape[0], nx);
  ASSERT_EQ(image.shape[1], ny);
  ASSERT_EQ(image.shape[2], nz);
  EXPECT_EQ(image.bits, 16);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        ASSERT_EQ(image.at(i, j, k), 1000 * k + 10 * (ny - 1 - j) + i) << i << " " << j << " " << k;
}

TEST(ImageReader, TiledTiffIsReadWholeAcrossPartialTiles) {
  // 20 x 18 in tiles of 16: three of the four tiles reach past the image.
  TiffPage page;
  page.tile = 16;
  page.picture = {20, 18, {}};
  for (int r = 0; r < 18; ++r)
    for (int i = 0; i < 20; ++i) page.picture.values.push_back(r * 20 + i < 256 ? r * 20 + i : 255);
  const auto path = temp_path("tiled.tif");
  write_tiff(path, {page});
  const auto image = read_tiff(path);
  ASSERT_EQ(image.shape[0], 20);
  ASSERT_EQ(image.shape[1], 18);
  for (int r = 0; r < 18; ++r)
    for (int i = 0; i < 20; ++i) ASSERT_EQ(image.at(i, 17 - r), page.picture.values[r * 20 + i]) << i << " " << r;
}

TEST(ImageReader, BadTiffsAreRefusedSayingWhy) {
  TiffPage rgb;
  rgb.samples = 3;
  rgb.photometric = PHOTOMETRIC_RGB;
  rgb.picture = {1, 1, {10, 20, 30}};
  const auto colour = temp_path("rgb.tif");
  write_tiff(colour, {rgb});
  EXPECT_MENTIONS(error_of([&] { read_tiff(colour); }), "colour");

  TiffPage real;
  real.bits = 32;
  real.format = SAMPLEFORMAT_IEEEFP;
  real.picture = {2, 1, {0, 1}};
  const auto floating = temp_path("float.tif");
  write_tiff(floating, {real});
  EXPECT_MENTIONS(error_of([&] { read_tiff(floating); }), "floating-point");

  TiffPage small, large;
  small.picture = {2, 2, {0, 1, 2, 3}};
  large.picture = {3, 2, {0, 1, 2, 3, 4, 5}};
  const auto mixed = temp_path("mixed.tif");
  write_tiff(mixed, {small, large});
  const auto mixed_error = error_of([&] { read_tiff(mixed); });
  EXPECT_MENTIONS(mixed_error, "page 2 is 3 x 2");

  TiffPage big;
  big.picture = {64, 64, std::vector<unsigned>(64 * 64, 7)};
  const auto cut = temp_path("truncated.tif");
  write_tiff(cut, {big, big});
  truncate_to(cut, fs::file_size(cut) / 2);  // within page 1's directory, written after its pixels
  EXPECT_MENTIONS(error_of([&] { read_tiff(cut); }), "unreadable");
  // Page 1 whole, page 2 cut: its directory is beyond the end.
  write_tiff(cut, {big, big});
  truncate_to(cut, fs::file_size(cut) * 3 / 4);
  EXPECT_MENTIONS(error_of([&] { read_tiff(cut); }), "page 2 is unreadable");
  const auto text = temp_path("text.tif");
  std::ofstream(text) << "not a picture\n";
  EXPECT_MENTIONS(error_of([&] { read_tiff(text); }), "unreadable TIFF");
  EXPECT_MENTIONS(error_of([&] { read_tiff(temp_path("missing.tif")); }), "no such file");
}

TEST(ImageReader, RawIsXFastestThenYThenZWithoutAFlip) {
  const auto path8 = temp_path("axes.raw");
  write_bytes(path8, {1, 2, 3, 4, 5, 6});
  const auto flat = read_raw(path8, {{3, 2}, 8});
  ASSERT_EQ(flat.dimension, 2);
  EXPECT_EQ(flat.at(0, 0), 1);
  EXPECT_EQ(flat.at(2, 0), 3);
  EXPECT_EQ(flat.at(0, 1), 4);
  EXPECT_EQ(flat.at(2, 1), 6);
  // 2 x 2 x 2 of little-endian uint16: value n + 256 (n + 1) at the n-th voxel.
  std::vector<unsigned char> bytes;
  for (int n = 0; n < 8; ++n)
    bytes.insert(bytes.end(), {static_cast<unsigned char>(n), static_cast<unsigned char>(n + 1)});
  const auto path16 = temp_path("volume.raw");
  write_bytes(path16, bytes);
  const auto volume = read_raw(path16, {{2, 2, 2}, 16});
  ASSERT_EQ(volume.dimension, 3);
  EXPECT_EQ(volume.bits, 16);
  EXPECT_EQ(volume.at(0, 0, 0), 256);
  EXPECT_EQ(volume.at(1, 0, 0), 1 + 2 * 256);
  EXPECT_EQ(volume.at(0, 1, 0), 2 + 3 * 256);
  EXPECT_EQ(volume.at(0, 0, 1), 4 + 5 * 256);
  EXPECT_EQ(volume.at(1, 1, 1), 7 + 8 * 256);
}

TEST(ImageReader, RawOfAnotherSizeThanItsShapeIsRefused) {
  const auto path = temp_path("short.raw");
  write_bytes(path, {1, 2, 3, 4, 5});
  const auto shorter = error_of([&] { read_raw(path, {{3, 2}, 8}); });
  EXPECT_MENTIONS(shorter, "holds 5 bytes");
  EXPECT_MENTIONS(shorter, "3 x 2");
  EXPECT_MENTIONS(shorter, "needs 6");
  EXPECT_MENTIONS(shorter, "cut short");
  // Six bytes are 3 x 2 of uint8, not of uint16.
  write_bytes(path, {1, 2, 3, 4, 5, 6});
  EXPECT_MENTIONS(error_of([&] { read_raw(path, {{3, 2}, 16}); }), "uint16 needs 12");
  EXPECT_MENTIONS(error_of([&] { read_raw(path, {{2, 2}, 8}); }), "holds 6 bytes");
  EXPECT_MENTIONS(error_of([&] { read_raw(path, {{6}, 8}); }), "Image/Shape");
  EXPECT_MENTIONS(error_of([&] { read_raw(path, {{3, 0}, 8}); }), "at least one voxel");
}

TEST(ImageReader, FormatIsChosenByExtensionInAnyCase) {
  const auto png = temp_path("upper.PNG");
  write_png(png, asymmetric(), 8);
  expect_asymmetric_axes(read_image(png, {}));
  const auto raw = temp_path("raw.RAW");
  write_bytes(raw, {1, 2, 3, 4, 5, 6});
  EXPECT_EQ(read_image(raw, {{3, 2}, 8}).at(0, 1), 4);
  const auto bmp = temp_path("image.bmp");
  write_bytes(bmp, {1, 2, 3});
  EXPECT_MENTIONS(error_of([&] { read_image(bmp, {}); }), "unknown image format '.bmp'");
}

// --- HDF5 datasets and windows ----------------------------------------

// A dataset of `type` holding `values` in the order given, of dims slowest first.
void write_hdf5_dataset(const std::string& path, const std::string& name, hid_t type,
                        const std::vector<hsize_t>& dims, const std::vector<long long>& values) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  const hid_t links = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(links, 1);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t set = H5Dcreate2(file, name.c_str(), type, space, links, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(set, 0) << name;
  ASSERT_GE(H5Dwrite(set, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(set);
  H5Sclose(space);
  H5Pclose(links);
  H5Fclose(file);
}

// An image's source, member by member (GCC 12 warns of a maybe-uninitialized
// vector in the nested aggregate ImageSource{path, {}, ...}).
ImageSource source_of(const std::string& path, const std::string& dataset = "", const RawLayout& raw = {}) {
  ImageSource source;
  source.path = path;
  source.dataset = dataset;
  source.raw = raw;
  return source;
}

TEST(ImageReader, Hdf5IsZYXAsStoredLikeRaw) {
  const auto flat = temp_path("flat.h5");
  write_hdf5_dataset(flat, "/image", H5T_STD_U8LE, {2, 3}, {1, 2, 3, 4, 5, 6});
  const auto plane = read_hdf5(flat, "/image");
  ASSERT_EQ(plane.dimension, 2);
  EXPECT_EQ(plane.bits, 8);
  EXPECT_EQ(plane.shape, (std::array<long long, 3>{{3, 2, 1}}));
  EXPECT_EQ(plane.at(0, 0), 1);
  EXPECT_EQ(plane.at(2, 0), 3);
  EXPECT_EQ(plane.at(0, 1), 4);
  // [z][y][x] of int32: 16 bits, value 100 z + 10 y + x.
  std::vector<long long> values;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) values.push_back(100 * z + 10 * y + x);
  const auto volume_path = temp_path("volume.hdf5");
  write_hdf5_dataset(volume_path, "/scan/segmented", H5T_STD_I32BE, {2, 3, 4}, values);
  const auto volume = read_image(source_of(volume_path, "/scan/segmented"));
  ASSERT_EQ(volume.dimension, 3);
  EXPECT_EQ(volume.bits, 16);
  EXPECT_EQ(volume.shape, (std::array<long long, 3>{{4, 3, 2}}));
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) EXPECT_EQ(volume.at(x, y, z), 100 * z + 10 * y + x);
  const auto header = read_image_header(source_of(volume_path, "scan/segmented"));
  EXPECT_EQ(header.shape, volume.shape);
}

TEST(ImageReader, Hdf5ProblemsAreNamed) {
  const auto path = temp_path("labels.h5");
  write_hdf5_dataset(path, "/scan/segmented", H5T_STD_U16LE, {2, 2}, {0, 1, 2, 3});
  const auto missing = error_of([&] { read_hdf5(path, "/scan/labels"); });
  EXPECT_MENTIONS(missing, "Image/Dataset '/scan/labels' is not in the file");
  EXPECT_MENTIONS(missing, "'/scan/segmented'");  // what is there
  EXPECT_MENTIONS(error_of([&] { read_hdf5(path, "/nothing/here"); }), "'/nothing' is missing");
  EXPECT_MENTIONS(error_of([&] { read_hdf5(path, "/scan"); }), "a group, not a dataset");
  const ImageSource without_dataset = source_of(path);
  const auto none = error_of([&] { read_image(without_dataset); });
  EXPECT_MENTIONS(none, "needs Image/Dataset");
  EXPECT_MENTIONS(none, "'/scan/segmented'");
  const auto line = temp_path("line.h5");
  write_hdf5_dataset(line, "/image", H5T_STD_U8LE, {4}, {0, 1, 0, 1});
  EXPECT_MENTIONS(error_of([&] { read_hdf5(line, "/image"); }), "has 1 dimensions");
  const auto real = temp_path("real.h5");
  write_hdf5_dataset(real, "/image", H5T_IEEE_F32LE, {2, 2}, {0, 1, 0, 1});
  EXPECT_MENTIONS(error_of([&] { read_hdf5(real, "/image"); }), "floating-point values");
  const auto negative = temp_path("negative.h5");
  write_hdf5_dataset(negative, "/image", H5T_STD_I32LE, {2, 2}, {0, 1, -5, 1});
  EXPECT_MENTIONS(error_of([&] { read_hdf5(negative, "/image"); }), "the label -5 at voxel (0, 1, 0)");
  const auto large = temp_path("large.h5");
  write_hdf5_dataset(large, "/image", H5T_STD_U32LE, {1, 2}, {0, 70000});
  EXPECT_MENTIONS(error_of([&] { read_hdf5(large, "/image"); }), "70000");
  const auto text = temp_path("text.h5");
  write_bytes(text, {'n', 'o', 't', ' ', 'h', 'd', 'f', '5', ' ', 'a', 't', ' ', 'a', 'l', 'l'});
  EXPECT_MENTIONS(error_of([&] { read_hdf5(text, "/image"); }), "HDF5");
  EXPECT_MENTIONS(error_of([&] { read_hdf5(temp_path("absent.h5"), "/image"); }), "no such file");
  const auto raw = temp_path("dataset.raw");
  write_bytes(raw, {1, 2, 3, 4});
  const ImageSource raw_with_dataset = source_of(raw, "/image", {{2, 2}, 8});
  EXPECT_MENTIONS(error_of([&] { read_image(raw_with_dataset); }),
                  "only an HDF5 file (.h5, .hdf5) holds datasets");
}

// 5 x 4 x 3 voxels, value 100 z + 10 y + x + 1, in every format that holds a volume, and its first page as a PNG.
struct NumberedVolume {
  VoxelImage whole;
  std::vector<ImageSource> sources;
  ImageSource png;
};

NumberedVolume numbered_volume() {
  NumberedVolume v;
  v.whole.dimension = 3;
  v.whole.shape = {5, 4, 3};
  v.whole.values.resize(60);
  std::vector<long long> zyx;
  std::vector<unsigned char> bytes;
  std::vector<TiffPage> strips(3), tiles(3);
  for (int z = 0; z < 3; ++z) {
    Picture page{5, 4, {}};
    for (int r = 0; r < 4; ++r)
      for (int x = 0; x < 5; ++x) page.values.push_back(100 * z + 10 * (3 - r) + x + 1);  // row r is y = 3 - r
    strips[z].picture = tiles[z].picture = page;
    tiles[z].tile = 16;
    strips[z].compression = COMPRESSION_LZW;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 5; ++x) {
        const auto value = static_cast<std::uint16_t>(100 * z + 10 * y + x + 1);
        v.whole.values[v.whole.index(x, y, z)] = value;
        zyx.push_back(value);
        bytes.insert(bytes.end(), {static_cast<unsigned char>(value & 0xff), static_cast<unsigned char>(value >> 8)});
      }
  }
  v.whole.bits = 16;
  const auto raw = temp_path("numbered.raw"), strip = temp_path("numbered.tif"), tiled = temp_path("tiled.tiff"),
             h5 = temp_path("numbered.h5"), png = temp_path("numbered.png");
  write_bytes(raw, bytes);
  write_tiff(strip, strips);
  write_tiff(tiled, tiles);
  write_hdf5_dataset(h5, "/image", H5T_STD_U16LE, {3, 4, 5}, zyx);
  Picture first{5, 4, {}};
  for (int r = 0; r < 4; ++r)
    for (int x = 0; x < 5; ++x) first.values.push_back(10 * (3 - r) + x + 1);
  write_png(png, first, 16);
  v.sources = {source_of(raw, "", {{5, 4, 3}, 16}), source_of(strip), source_of(tiled), source_of(h5, "/image")};
  v.png = source_of(png);
  return v;
}

TEST(ImageReader, WindowsHoldTheirLayersWrappedAndReflected) {
  const auto volume = numbered_volume();
  // Across the periodic face along x (4, 0, 1), reflected along y (3, 3, 2, 1), and z out of order.
  ImageWindow window;
  window.source = {{{4, 0, 1}, {3, 3, 2, 1}, {2, 0}}};
  const auto expected = take_window(volume.whole, window);
  EXPECT_EQ(expected.shape, (std::array<long long, 3>{{3, 4, 2}}));
  EXPECT_EQ(expected.at(0, 0, 0), 200 + 30 + 4 + 1);
  EXPECT_EQ(expected.at(1, 3, 1), 0 + 10 + 0 + 1);
  for (const auto& source : volume.sources) {
    SCOPED_TRACE(source.path);
    EXPECT_EQ(read_image_header(source).shape, volume.whole.shape);
    EXPECT_EQ(read_image(source).values, volume.whole.values);
    const auto piece = read_image_window(source, window);
    EXPECT_EQ(piece.shape, expected.shape);
    EXPECT_EQ(piece.values, expected.values);
    long long declared = 0;
    read_image_window(source, window, [&](long long voxels, const std::string&) {
      if (declared == 0) declared = voxels;  // (a tiled TIFF's tiles are asked about after)
    });
    EXPECT_EQ(declared, 3 * 4 * 2);  // the memory check is asked about the window, not the whole file
    ImageWindow beyond;
    beyond.source[2] = {3};
    EXPECT_MENTIONS(error_of([&] { read_image_window(source, beyond); }), "layer 3 along z");
  }
  ImageWindow plane;
  plane.source = {{{1, 2}, {0, 3}, {}}};
  VoxelImage first = volume.whole;
  first.dimension = 2;
  first.shape[2] = 1;
  first.values.resize(20);
  EXPECT_EQ(read_image_window(volume.png, plane).values, take_window(first, plane).values);
}

TEST(VoxelImage, MirrorRepeatsTheImageBackwardsAlongOneAxis) {
  VoxelImage image;
  image.shape = {3, 2, 1};
  image.values = {1, 2, 3, 4, 5, 6};
  const auto along_x = mirrored(image, 0);
  ASSERT_EQ(along_x.shape[0], 6);
  ASSERT_EQ(along_x.shape[1], 2);
  const std::vector<std::uint16_t> x_expected = {1, 2, 3, 3, 2, 1, 4, 5, 6, 6, 5, 4};
  EXPECT_EQ(along_x.values, x_expected);
  const auto along_y = mirrored(image, 1);
  ASSERT_EQ(along_y.shape[1], 4);
  const std::vector<std::uint16_t> y_expected = {1, 2, 3, 4, 5, 6, 4, 5, 6, 1, 2, 3};
  EXPECT_EQ(along_y.values, y_expected);
  EXPECT_THROW(mirrored(image, 2), std::invalid_argument);  // no z in 2D
}

TEST(VoxelImage, SolidValuesSplitTheVoxels) {
  VoxelImage image;
  image.shape = {4, 1, 1};
  image.bits = 16;
  image.values = {0, 7, 65535, 7};
  const auto counts = count_voxels(image, {7, 65535});
  EXPECT_EQ(counts.solid, 3);
  EXPECT_EQ(counts.pore, 1);
  EXPECT_EQ(count_voxels(image, {3}).solid, 0);
}

using testing::sketch;

constexpr std::array<bool, 3> kPeriodic{{true, true, true}};

TEST(Percolation, OpenChannelCarriesFlowAlongItOnly) {
  const auto channel = sketch({"######",
                               "......",
                               "######"});
  EXPECT_TRUE(pore_percolates(channel, {1}, 0, kPeriodic));
  EXPECT_FALSE(pore_percolates(channel, {1}, 1, kPeriodic));
  // Bounded in x, the channel still joins the two faces.
  EXPECT_TRUE(pore_percolates(channel, {1}, 0, {false, true, true}));
}

TEST(Percolation, PoresTouchingBothFacesButClosedInsideDoNotCount) {
  // The row's two ends meet through the periodic face, but the solid in the
  // middle closes it: one cluster that does not reach its own image.
  const auto closed = sketch({"######",
                              "..#...",
                              "######"});
  EXPECT_FALSE(pore_percolates(closed, {1}, 0, kPeriodic));
  // Bounded in x the closed row has no face-to-face path either.
  EXPECT_FALSE(pore_percolates(closed, {1}, 0, {false, true, true}));
  // A band down and to the right: it reaches its own image along x only
  // through the periodic y face, from the bottom row back to the top.
  const auto around = sketch({"..##",
                              "#..#",
                              "##..",
                              ".##."});
  EXPECT_TRUE(pore_percolates(around, {1}, 0, kPeriodic));
  EXPECT_FALSE(pore_percolates(around, {1}, 0, {true, false, true}));
}

TEST(Percolation, VoxelsMeetingAtACornerLeaveNoPath) {
  const auto corners = sketch({"#.#.#.",
                               ".#.#.#"});
  EXPECT_FALSE(pore_percolates(corners, {1}, 0, kPeriodic));
  const auto stair = sketch({"##.###",
                             "#..###",
                             "..####",
                             "######"});
  EXPECT_FALSE(pore_percolates(stair, {1}, 0, kPeriodic));
  EXPECT_FALSE(pore_percolates(stair, {1}, 1, kPeriodic));
}

TEST(Percolation, TubeAlongZOfAVolume) {
  VoxelImage block;
  block.dimension = 3;
  block.shape = {4, 4, 5};
  block.values.assign(static_cast<size_t>(block.count()), 1);
  for (long long k = 0; k < 5; ++k) block.values[block.index(1, 2, k)] = 0;
  EXPECT_TRUE(pore_percolates(block, {1}, 2, kPeriodic));
  EXPECT_FALSE(pore_percolates(block, {1}, 0, kPeriodic));
  EXPECT_FALSE(pore_percolates(block, {1}, 1, kPeriodic));
  block.values[block.index(1, 2, 3)] = 1;  // plugged
  EXPECT_FALSE(pore_percolates(block, {1}, 2, kPeriodic));
}

// --- the Image parameters ------------------------------------------------

using testing::array;

// 3 x 2 voxels of 0.1 m in a 0.3 x 0.2 cell, solid where the value is 6.
ParameterList image_scene(const std::string& file) {
  ParameterList list = testing::minimal_scene();
  list.sublist("Domain").set("Cell Size", array<double>({0.3, 0.2}));
  list.sublist("Discretization").set("Particle Spacing", 0.01);
  auto& image = list.sublist("Image");
  image.set("File", file);
  image.set("Solid Values", array<int>({6}));
  image.set("Voxel Size", 0.1);
  return list;
}

std::string scene_error(ParameterList list, const std::string& directory = "") {
  return error_of<ParameterError>([&] {
    validate_parameters(list);
    scene_from_parameters(list, directory);
  });
}

class ImageParameters : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(folder);
    write_png(png, asymmetric(), 8);
  }
  void TearDown() override { fs::remove_all(folder); }
  const std::string folder = temp_path("scene");
  const std::string png = folder + "/sample.png";
};

TEST_F(ImageParameters, ImageIsReadRelativeToTheSceneFolder) {
  auto list = image_scene("sample.png");
  validate_parameters(list);
  const auto scene = scene_from_parameters(list, folder);
  ASSERT_TRUE(scene.image.voxels);
  EXPECT_EQ(scene.image.file, png);
  expect_asymmetric_axes(*scene.image.voxels);
  EXPECT_EQ(scene.image.counts.solid, 1);
  EXPECT_EQ(scene.image.counts.pore, 5);
  EXPECT_EQ(scene.image.mirror_axis, -1);
  EXPECT_TRUE(scene.grains.empty());
  // The run's checks accept it (the lattice is filled from the image,
  // tests/test_image_solid.cpp), counting the image in each process's memory.
  auto copy = scene;
  MemoryBudget budget;
  budget.available_bytes = 1e12;
  EXPECT_EQ(error_of<ParameterError>([&] { check_scene(copy, 1, budget); }), "");
  auto larger = copy;  // 1000 voxels more: 10 bytes each, values and distance field
  auto voxels = std::make_shared<VoxelImage>(*copy.image.voxels);
  voxels->shape = {1006, 1, 1};
  voxels->values.resize(1006);
  larger.image.voxels = voxels;
  EXPECT_NEAR(check_scene(larger, 1, budget).bytes_per_process - check_scene(copy, 1, budget).bytes_per_process,
              10.0 * 1000, 1e-6);
  // A scene without an image has none.
  auto plain = image_scene("");
  plain.sublist("Image").remove("Solid Values");
  plain.sublist("Image").remove("Voxel Size");
  validate_parameters(plain);
  EXPECT_FALSE(scene_from_parameters(plain, folder).image.voxels);
}

TEST_F(ImageParameters, CellOtherThanTheImageIsRefusedNamingBoth) {
  auto list = image_scene(png);
  list.sublist("Domain").set("Cell Size", array<double>({0.3, 0.25}));
  const auto error = scene_error(list);
  EXPECT_MENTIONS(error, "Domain/Cell Size {0.3, 0.25}");
  EXPECT_MENTIONS(error, "{0.3, 0.2}");
  EXPECT_MENTIONS(error, "Image/Voxel Size 0.1");
  // Within 1e-9 relative it is the same cell; beyond, not.
  list.sublist("Domain").set("Cell Size", array<double>({0.3 * (1 + 5e-10), 0.2}));
  EXPECT_EQ(scene_error(list), "");
  list.sublist("Domain").set("Cell Size", array<double>({0.3 * (1 + 5e-9), 0.2}));
  EXPECT_MENTIONS(scene_error(list), "Domain/Cell Size");
}

TEST_F(ImageParameters, ImageAndGrainsExcludeEachOther) {
  auto list = image_scene(png);
  list.sublist("Grains").set("Inline", array<double>({0.1, 0.1, 0.02}));
  EXPECT_MENTIONS(scene_error(list), "a scene uses one of them");
  auto packed = image_scene(png);
  packed.sublist("Grains").sublist("Random Pack").set("Porosity", 0.5);
  EXPECT_MENTIONS(scene_error(packed), "a scene uses one of them");
}

TEST_F(ImageParameters, RequiredAndOrphanedValuesAreNamed) {
  auto no_solid = image_scene(png);
  no_solid.sublist("Image").remove("Solid Values");
  EXPECT_MENTIONS(scene_error(no_solid), "Image/Solid Values is required");
  auto no_size = image_scene(png);
  no_size.sublist("Image").remove("Voxel Size");
  EXPECT_MENTIONS(scene_error(no_size), "Image/Voxel Size is required");
  auto orphan = image_scene("");
  EXPECT_MENTIONS(scene_error(orphan), "Image/Solid Values is given but Image/File is empty");
  auto out_of_range = image_scene(png);
  out_of_range.sublist("Image").set("Solid Values", array<int>({70000}));
  EXPECT_MENTIONS(scene_error(out_of_range), "Solid Values");
  auto beyond_8_bits = image_scene(png);
  beyond_8_bits.sublist("Image").set("Solid Values", array<int>({6, 300}));
  EXPECT_MENTIONS(scene_error(beyond_8_bits), "300 cannot occur");
}

// A slit one voxel wide carries flow in the voxels, but the walls placed
// between the voxels close it: refused, saying so, rather than run with the
// flow lost.
TEST_F(ImageParameters, OneVoxelGapsThatCloseBetweenTheWallsAreRefused) {
  const auto raw = folder + "/slit.raw";
  write_bytes(raw, {6, 6, 6, 0, 0, 0, 6, 6, 6});  // 3 x 3 voxels: one row of pore
  auto list = image_scene(raw);
  list.sublist("Domain").set("Cell Size", array<double>({0.3, 0.3}));
  list.sublist("Image").set("Shape", array<int>({3, 3}));
  EXPECT_MENTIONS(scene_error(list), "close when the walls are placed between the voxels");
}

// A sample that is not periodic along x: a wedge of solid above a channel
// four voxels high, 12 voxels tall at x = 0 and gone from x = 12 on, so that
// neighbouring layers differ in at most one voxel of 16 and the two faces
// in 12. Warned of, naming the axis and the remedy; mirrored along x (the
// driven axis), the faces match and the warning goes. Across y the faces
// differ in one voxel of 16, less than the layers inside: no warning.
TEST_F(ImageParameters, FacesThatDoNotMatchAcrossThePeriodicCellAreWarnedOf) {
  const auto raw = folder + "/wedge.raw";
  std::vector<unsigned char> wedge;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) wedge.push_back(j >= 4 && j < 16 - i ? 6 : 0);
  write_bytes(raw, wedge);
  auto list = image_scene(raw);
  list.sublist("Domain").set("Cell Size", array<double>({1.6, 1.6}));
  list.sublist("Image").set("Shape", array<int>({16, 16}));
  validate_parameters(list);
  const auto scene = scene_from_parameters(list, folder);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_MENTIONS(scene.warnings[0], "faces across x differ in 75 % of their voxels");
  EXPECT_MENTIONS(scene.warnings[0], "Image/Mirror");
  auto mirrored_list = list;
  mirrored_list.sublist("Image").set("Mirror", true);
  mirrored_list.sublist("Domain").set("Cell Size", array<double>({3.2, 1.6}));
  const auto mirrored_scene = scene_from_parameters(mirrored_list, folder);
  EXPECT_TRUE(mirrored_scene.warnings.empty());
}

// An image too large to make walls of in the memory there is: refused
// before the distance field is made, with what it needs and what there is.
TEST_F(ImageParameters, ImageTooLargeForTheMemoryIsRefusedBeforeItsWallsAreMade) {
  const auto raw = folder + "/large.raw";
  write_bytes(raw, std::vector<unsigned char>(48, 0));  // 6 x 8 voxels: 1920 bytes to set up
  auto list = image_scene(raw);
  list.sublist("Domain").set("Cell Size", array<double>({0.6, 0.8}));
  list.sublist("Image").set("Shape", array<int>({6, 8}));
  list.sublist("Run").set("Memory Limit", 1e-6);  // GB: 1000 bytes
  const auto error = scene_error(list);
  EXPECT_MENTIONS(error, "making its walls takes about 1.92e-06 GB");
  EXPECT_MENTIONS(error, "Run/Memory Limit");
  list.sublist("Run").set("Memory Limit", 1e-5);  // 10,000 bytes: enough (the all-pore image is refused later)
  EXPECT_EQ(scene_error(list).find("making its walls"), std::string::npos);
}

// The pore check of an image: a band of pore five voxels wide between
// bands of solid three wide (periodic), along x. The walls fall on the
// voxel faces, and the widest path along x is the band: 0.5 m wide at its
// narrowest. Spacings Across Throat divides that width.
TEST_F(ImageParameters, NarrowestPoreIsTheWidestPathsBottleneck) {
  const auto raw = folder + "/band.raw";
  std::vector<unsigned char> band;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 6; ++i) band.push_back(j < 3 ? 6 : 0);
  write_bytes(raw, band);
  auto banded = [&](double spacing) {
    auto list = image_scene(raw);
    list.sublist("Domain").set("Cell Size", array<double>({0.6, 0.8}));
    list.sublist("Image").set("Shape", array<int>({6, 8}));
    list.sublist("Discretization").set("Particle Spacing", spacing);
    return list;
  };
  auto across = banded(0.0);
  across.sublist("Discretization").remove("Particle Spacing");
  across.sublist("Discretization").set("Spacings Across Throat", 5.0);
  validate_parameters(across);
  const auto scene = scene_from_parameters(across, folder);
  EXPECT_NEAR(scene.image.bottleneck[0], 0.5, 1e-6);
  EXPECT_EQ(scene.image.bottleneck[1], 0.0);  // not driven along y
  EXPECT_NEAR(scene.particle_spacing, 0.1, 1e-12);
  EXPECT_TRUE(scene.warnings.empty());
  auto under_three = banded(0.2);
  validate_parameters(under_three);
  const auto warned = scene_from_parameters(under_three, folder);
  ASSERT_EQ(warned.warnings.size(), 2u);
  EXPECT_MENTIONS(warned.warnings[0], "widest pore path along x narrows to 0.5 (5 voxels, 2.5 particle spacings)");
  // ... and the whole band is narrower than three spacings: no ball 0.6 m across fits in it.
  EXPECT_MENTIONS(warned.warnings[1], "100 % of its pore volume lies in passages narrower than 3 particle spacings");
  EXPECT_MENTIONS(scene_error(banded(0.6)), "narrower than one spacing");
}

TEST_F(ImageParameters, AllSolidOrAllPoreIsRefused) {
  auto none_solid = image_scene(png);
  none_solid.sublist("Image").set("Solid Values", array<int>({0, 7}));
  EXPECT_MENTIONS(scene_error(none_solid), "no solid voxels");
  auto all_solid = image_scene(png);
  all_solid.sublist("Image").set("Solid Values", array<int>({1, 2, 3, 4, 5, 6}));
  EXPECT_MENTIONS(scene_error(all_solid), "no pore voxels");
}

TEST_F(ImageParameters, ImageWithoutAPorePathAlongTheFlowIsRefusedNamingTheAxis) {
  // Solid 2 and 5, the middle column: the pores cross the cell along y, not along x.
  auto blocked = image_scene(png);
  blocked.sublist("Image").set("Solid Values", array<int>({2, 5}));
  const auto error = scene_error(blocked);
  EXPECT_MENTIONS(error, "no pore path crosses the cell along x, the driven axis");
  EXPECT_MENTIONS(error, "{2, 5}");
  blocked.sublist("Fluid").set("Body Force", array<double>({0.0, 1e-3}));
  EXPECT_EQ(scene_error(blocked), "");
  blocked.sublist("Permeability").set("Tensor", true);  // every axis is driven in turn
  EXPECT_MENTIONS(scene_error(blocked), "along x (Permeability/Tensor");
}

TEST_F(ImageParameters, ShapeAndDimensionAreCheckedAgainstTheFile) {
  auto wrong_shape = image_scene(png);
  wrong_shape.sublist("Image").set("Shape", array<int>({2, 3}));
  EXPECT_MENTIONS(scene_error(wrong_shape), "is not of Image/Shape {2, 3}");
  auto right_shape = image_scene(png);
  right_shape.sublist("Image").set("Shape", array<int>({3, 2}));
  EXPECT_EQ(scene_error(right_shape), "");
  auto three_d = image_scene(png);
  three_d.sublist("Domain").set("Cell Size", array<double>({0.3, 0.2, 0.1}));
  three_d.sublist("Fluid").set("Body Force", array<double>({1e-3, 0.0, 0.0}));
  EXPECT_MENTIONS(scene_error(three_d), "is a 2D image, but Domain/Cell Size has 3 values");

  const auto raw = folder + "/sample.raw";
  write_bytes(raw, {1, 2, 3, 4, 5, 6});
  auto unshaped = image_scene(raw);
  EXPECT_MENTIONS(scene_error(unshaped), "Image/Shape is required for a .raw image");
  auto shaped = image_scene(raw);
  shaped.sublist("Image").set("Shape", array<int>({3, 2}));
  EXPECT_EQ(scene_error(shaped), "");
  shaped.sublist("Image").set("Type", std::string("uint16"));
  EXPECT_MENTIONS(scene_error(shaped), "uint16 needs 12");
  auto broken = image_scene(folder + "/missing.png");
  EXPECT_MENTIONS(scene_error(broken), "no such file");
}

TEST_F(ImageParameters, MirrorDoublesTheCellAlongTheDrivenAxis) {
  auto list = image_scene(png);
  list.sublist("Image").set("Mirror", true);
  EXPECT_MENTIONS(scene_error(list), "after Image/Mirror");  // the cell is still the unmirrored image
  list.sublist("Domain").set("Cell Size", array<double>({0.6, 0.2}));
  validate_parameters(list);
  const auto scene = scene_from_parameters(list);
  EXPECT_EQ(scene.image.mirror_axis, 0);
  ASSERT_EQ(scene.image.voxels->shape[0], 6);
  EXPECT_EQ(scene.image.voxels->at(3, 1), 3);  // the top row 1 2 3 | 3 2 1
  EXPECT_EQ(scene.image.voxels->at(5, 1), 1);
  EXPECT_EQ(scene.image.counts.solid, 2);

  // Driven along y: mirrored along y.
  auto along_y = image_scene(png);
  along_y.sublist("Image").set("Mirror", true);
  along_y.sublist("Fluid").set("Body Force", array<double>({0.0, 1e-3}));
  along_y.sublist("Domain").set("Cell Size", array<double>({0.3, 0.4}));
  validate_parameters(along_y);
  EXPECT_EQ(scene_from_parameters(along_y).image.mirror_axis, 1);

  auto tensor = image_scene(png);
  tensor.sublist("Image").set("Mirror", true);
  tensor.sublist("Permeability").set("Tensor", true);
  EXPECT_MENTIONS(scene_error(tensor), "Permeability/Tensor");
  auto undriven = image_scene(png);
  undriven.sublist("Image").set("Mirror", true);
  undriven.sublist("Fluid").set("Body Force", array<double>({1e-3, 1e-3}));
  EXPECT_MENTIONS(scene_error(undriven), "must lie along one axis");
}

TEST_F(ImageParameters, Hdf5DatasetIsNamedByImageDataset) {
  const auto h5 = folder + "/sample.h5";
  write_hdf5_dataset(h5, "/segmented", H5T_STD_U8LE, {2, 3}, {4, 5, 6, 1, 2, 3});
  auto list = image_scene("sample.h5");
  list.sublist("Image").set("Dataset", std::string("/segmented"));
  validate_parameters(list);
  const auto scene = scene_from_parameters(list, folder);
  EXPECT_EQ(scene.image.counts.solid, 1);
  EXPECT_EQ(scene.image.voxels->at(2, 0), 6);  // the PNG's axes: the same image as sample.png
  auto from_png = image_scene(png);
  validate_parameters(from_png);
  EXPECT_EQ(scene.image.voxels->values, scene_from_parameters(from_png, folder).image.voxels->values);
  list.sublist("Image").set("Dataset", std::string("/labels"));
  EXPECT_MENTIONS(scene_error(list, folder), "Image/Dataset '/labels' is not in the file");
  auto for_png = image_scene(png);
  for_png.sublist("Image").set("Dataset", std::string("/segmented"));
  EXPECT_MENTIONS(scene_error(for_png, folder), "only an HDF5 file");
  auto orphan = testing::minimal_scene();
  orphan.sublist("Image").set("Dataset", std::string("/segmented"));
  EXPECT_MENTIONS(scene_error(orphan), "Image/Dataset is given but Image/File is empty");
}

TEST_F(ImageParameters, ImageIsGivenFromXmlAndSet) {
  const auto xml = folder + "/scene.xml";
  std::ofstream(xml) << R"xml(<ParameterList name="PoreSPH">
  <ParameterList name="Domain"><Parameter name="Cell Size" type="Array(double)" value="{0.3, 0.2}"/></ParameterList>
  <ParameterList name="Fluid"><Parameter name="Kinematic Viscosity" type="double" value="0.01"/>
    <Parameter name="Body Force" type="Array(double)" value="{0.001, 0}"/></ParameterList>
  <ParameterList name="Discretization"><Parameter name="Particle Spacing" type="double" value="0.01"/></ParameterList>
  <ParameterList name="Run"><Parameter name="End Time" type="double" value="1"/></ParameterList>
  <ParameterList name="Image">
    <Parameter name="File" type="string" value="sample.png"/>
    <Parameter name="Solid Values" type="Array(int)" value="{6}"/>
    <Parameter name="Voxel Size" type="double" value="0.1"/>
  </ParameterList>
</ParameterList>
)xml";
  const auto list = read_parameters(xml, {"Image/Solid Values={5, 6}"});
  const auto scene = scene_from_parameters(*list, folder);
  EXPECT_EQ(scene.image.solid_values, (std::vector<int>{5, 6}));
  EXPECT_EQ(scene.image.counts.solid, 2);
  EXPECT_MENTIONS(error_of<ParameterError>([&] { read_parameters(xml, {"Image/Type=uint32"}); }), "uint32");
}

}  // namespace
}  // namespace poresph
