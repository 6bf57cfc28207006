#include "io/ImageReader.hpp"

#include <png.h>
#include <tiffio.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csetjmp>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>

#include "io/ImageWindowRuns.hpp"
#include "io/PathCheck.hpp"

namespace poresph {
namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw std::invalid_argument("Image/File '" + path + "': " + why);
}

// A directory or a device would read as an empty or endless image.
void check_regular_file(const std::string& path) {
  if (const std::string problem = regular_file_problem(path, "an image"); !problem.empty()) refuse(path, problem);
}

// "nx x ny" or "nx x ny x nz".
std::string shape_words(const std::vector<long long>& shape) {
  std::string text;
  for (size_t d = 0; d < shape.size(); ++d) text += (d ? " x " : "") + std::to_string(shape[d]);
  return text;
}

// The declared size, to the caller's check, before it is allocated.
void check_size(const ImageSizeCheck& check, long long voxels, const std::vector<long long>& shape) {
  if (check) check(voxels, shape_words(shape));
}

// nx * ny * nz, refused where it would not fit the memory's index.
long long voxel_count(const std::string& path, const std::vector<long long>& shape) {
  long long count = 1;
  for (long long n : shape) {
    if (n < 1) refuse(path, "every side of the image must hold at least one voxel");
    if (count > std::numeric_limits<long long>::max() / 8 / n) refuse(path, "the image is too large to index");
    count *= n;
  }
  return count;
}

const char* const kGreyOnly =
    "PoreSPH reads greyscale images (one value a voxel, 8 or 16 bits): save the segmentation as greyscale";

// --- PNG ---------------------------------------------------------------
// libpng reports an error by longjmp back into the function that called
// setjmp: the frames it crosses hold nothing with a destructor (this
// message buffer is plain data), and the message leaves as an exception
// only once libpng has returned.
struct PngError {
  char message[512] = "";
};

void png_error_handler(png_structp png, png_const_charp text) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof error->message, "%s", text);
  png_longjmp(png, 1);
}
void png_warning_handler(png_structp, png_const_charp) {}  // e.g. an unknown chunk: nothing a voxel depends on

bool png_read_header(png_structp png, png_infop info, std::FILE* file) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  return true;
}

bool png_read_pixels(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  // The chunks after the pixels too: a file cut short after its last pixel is truncated all the same.
  png_read_end(png, info);
  return true;
}

bool png_prepare(png_structp png, png_infop info) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_packing(png);  // 1, 2, 4 bits to one byte a pixel, values unchanged (not scaled to 255)
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return true;
}

struct PngReadStruct {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngReadStruct() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// --- TIFF --------------------------------------------------------------
// libtiff's messages go to this file's own handlers (not to stderr), the
// first error kept for the exception.
struct TiffError {
  char message[512] = "";
};

int tiff_error_handler(TIFF*, void* user, const char* module, const char* format, va_list args) {
  auto* error = static_cast<TiffError*>(user);
  if (error->message[0] != '\0') return 1;
  char text[400];
  std::vsnprintf(text, sizeof text, format, args);
  std::snprintf(error->message, sizeof error->message, "%s%s%s", module ? module : "", module ? ": " : "", text);
  return 1;
}
// Microscopes write private tags libtiff warns about; nothing a voxel depends on.
int tiff_warning_handler(TIFF*, void*, const char*, const char*, va_list) { return 1; }

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// A PNG opened and its header read and checked, its pixels not yet read.
struct OpenPng {
  File file{nullptr, &std::fclose};
  PngError error;
  PngReadStruct reader;
  ImageHeader header;
};

std::unique_ptr<OpenPng> open_png(const std::string& path) {
  check_regular_file(path);
  auto png = std::make_unique<OpenPng>();
  png->file.reset(std::fopen(path.c_str(), "rb"));
  if (!png->file) refuse(path, std::strerror(errno));
  png_byte signature[8];
  if (std::fread(signature, 1, 8, png->file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    refuse(path, "not a PNG file (it does not start with the PNG signature)");
  auto& reader = png->reader;
  reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &png->error, png_error_handler, png_warning_handler);
  if (!reader.png) refuse(path, "libpng could not start reading");
  reader.info = png_create_info_struct(reader.png);
  if (!reader.info) refuse(path, "libpng could not start reading");
  if (!png_read_header(reader.png, reader.info, png->file.get()))
    refuse(path, std::string("unreadable PNG: ") + png->error.message);

  const png_uint_32 width = png_get_image_width(reader.png, reader.info);
  const png_uint_32 height = png_get_image_height(reader.png, reader.info);
  const int depth = png_get_bit_depth(reader.png, reader.info);
  const int colour = png_get_color_type(reader.png, reader.info);
  if (colour == PNG_COLOR_TYPE_PALETTE)
    refuse(path, std::string("an indexed-colour (palette) PNG; ") + kGreyOnly);
  if (colour == PNG_COLOR_TYPE_RGB || colour == PNG_COLOR_TYPE_RGB_ALPHA)
    refuse(path, std::string("a colour PNG (RGB") + (colour == PNG_COLOR_TYPE_RGB_ALPHA ? "A" : "") + "); " +
                     kGreyOnly);
  if (colour == PNG_COLOR_TYPE_GRAY_ALPHA)
    refuse(path, std::string("a greyscale PNG with an alpha channel; ") + kGreyOnly + " without alpha");
  if (colour != PNG_COLOR_TYPE_GRAY) refuse(path, "a PNG of unknown colour type " + std::to_string(colour));
  png->header.dimension = 2;
  png->header.shape = {{static_cast<long long>(width), static_cast<long long>(height), 1}};
  png->header.bits = depth == 16 ? 16 : 8;
  return png;
}

// --- TIFF stacks ---------------------------------------------------------
struct OpenTiff {
  TiffError error;
  std::unique_ptr<TIFF, void (*)(TIFF*)> tiff{nullptr, &TIFFClose};
};

std::unique_ptr<OpenTiff> open_tiff(const std::string& path) {
  check_regular_file(path);
  auto open = std::make_unique<OpenTiff>();
  std::unique_ptr<TIFFOpenOptions, void (*)(TIFFOpenOptions*)> options(TIFFOpenOptionsAlloc(), &TIFFOpenOptionsFree);
  if (!options) refuse(path, "libtiff could not start reading");
  TIFFOpenOptionsSetErrorHandlerExtR(options.get(), tiff_error_handler, &open->error);
  TIFFOpenOptionsSetWarningHandlerExtR(options.get(), tiff_warning_handler, nullptr);
  open->tiff.reset(TIFFOpenExt(path.c_str(), "r", options.get()));
  if (!open->tiff) refuse(path, std::string("unreadable TIFF: ") + open->error.message);
  return open;
}

// Every page's tags, read without its pixels: one size, grey, unsigned, 8
// or 16 bits throughout, so that a stack is known whole before any of it
// is allocated.
ImageHeader tiff_header(OpenTiff& open, const std::string& path) {
  TIFF* tiff = open.tiff.get();
  long long pages = 0;
  std::uint32_t width = 0, height = 0;
  std::uint16_t bits = 0;
  do {
    const std::string page = "page " + std::to_string(pages + 1);
    std::uint32_t w = 0, h = 0;
    std::uint16_t samples = 1, b = 1, format = SAMPLEFORMAT_UINT, photometric = PHOTOMETRIC_MINISBLACK;
    if (!TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &h))
      refuse(path, page + " has no width or height");
    TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &b);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetField(tiff, TIFFTAG_PHOTOMETRIC, &photometric);  // absent: read as grey
    if (photometric == PHOTOMETRIC_PALETTE) refuse(path, page + " is an indexed-colour (palette) image; " + kGreyOnly);
    if (samples != 1 || (photometric != PHOTOMETRIC_MINISBLACK && photometric != PHOTOMETRIC_MINISWHITE))
      refuse(path, page + " is a colour image (" + std::to_string(samples) + " samples a pixel, photometric " +
                       std::to_string(photometric) + "); " + kGreyOnly);
    if (format != SAMPLEFORMAT_UINT)
      refuse(path, page + std::string(" holds ") + (format == SAMPLEFORMAT_IEEEFP ? "floating-point" : "signed") +
                       " samples; a segmented image holds unsigned labels of 8 or 16 bits");
    if (b != 8 && b != 16)
      refuse(path, page + " has " + std::to_string(b) + " bits a sample; 8 or 16 expected");
    if (pages == 0) {
      width = w, height = h, bits = b;
    } else if (w != width || h != height || b != bits) {
      refuse(path, page + " is " + std::to_string(w) + " x " + std::to_string(h) + " of " + std::to_string(b) +
                       " bits, page 1 " + std::to_string(width) + " x " + std::to_string(height) + " of " +
                       std::to_string(bits) + ": the pages of a stack are the z layers of one volume");
    }
    ++pages;
  } while (TIFFReadDirectory(tiff));
  // TIFFReadDirectory says 0 at the last page and on a damaged one alike; only the latter leaves a message.
  if (open.error.message[0] != '\0')
    refuse(path, "page " + std::to_string(pages + 1) + " is unreadable: " + open.error.message);
  ImageHeader header;
  header.dimension = pages > 1 ? 3 : 2;
  header.shape = {{static_cast<long long>(width), static_cast<long long>(height), pages}};
  header.bits = bits;
  return header;
}

// Page `page` into window layer `layer`: its rows (or tile rows) that the
// window holds, row r at y = h - 1 - r.
void read_tiff_page(OpenTiff& open, const std::string& path, const ImageHeader& header, const ImageWindow& window,
                    long long page, long long layer, const ImageSizeCheck& check, VoxelImage& image) {
  TIFF* tiff = open.tiff.get();
  const std::string name = "page " + std::to_string(page + 1);
  if (!TIFFSetDirectory(tiff, static_cast<tdir_t>(page)))
    refuse(path, name + " is unreadable: " + open.error.message);
  const auto w = static_cast<std::uint32_t>(header.shape[0]), h = static_cast<std::uint32_t>(header.shape[1]);
  const size_t bytes_per_value = header.bits / 8;
  // The window's y layers of each stored row, and the last row any is in.
  std::vector<std::vector<long long>> window_rows(h);
  std::uint32_t last_row = 0;
  for (long long y = 0; y < static_cast<long long>(window.source[1].size()); ++y) {
    const auto r = static_cast<std::uint32_t>(h - 1 - window.source[1][y]);
    window_rows[r].push_back(y);
    last_row = std::max(last_row, r);
  }
  // One stored row (or the part of it in a tile, from column `first`) into the window.
  auto put = [&](const unsigned char* data, std::uint32_t r, std::uint32_t first, std::uint32_t n) {
    for (long long y : window_rows[r])
      for (long long x = 0; x < image.shape[0]; ++x) {
        const long long column = window.source[0][x] - first;
        if (column < 0 || column >= n) continue;
        std::uint16_t v = data[column];
        if (bytes_per_value == 2) std::memcpy(&v, data + 2 * column, 2);  // libtiff gives native byte order
        image.values[image.index(x, y, layer)] = v;
      }
  };
  if (TIFFIsTiled(tiff)) {
    std::uint32_t tile_w = 0, tile_h = 0;
    TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &tile_w);
    TIFFGetField(tiff, TIFFTAG_TILELENGTH, &tile_h);
    if (tile_w == 0 || tile_h == 0) refuse(path, name + " is tiled with tiles of no size");
    // A tile is allocated whole: one declared far larger than the page is checked too.
    if (static_cast<long long>(tile_w) * tile_h > static_cast<long long>(w) * h)
      check_size(check, voxel_count(path, {tile_w, tile_h}), {tile_w, tile_h});
    std::vector<unsigned char> tile(static_cast<size_t>(TIFFTileSize(tiff)));
    if (tile.size() < size_t{tile_w} * tile_h * bytes_per_value) refuse(path, name + ": unexpected tile size");
    for (std::uint32_t y0 = 0; y0 <= last_row; y0 += tile_h) {
      bool wanted = false;
      for (std::uint32_t r = y0; r < std::min(h, y0 + tile_h); ++r) wanted = wanted || !window_rows[r].empty();
      if (!wanted) continue;
      for (std::uint32_t x0 = 0; x0 < w; x0 += tile_w) {
        if (TIFFReadTile(tiff, tile.data(), x0, y0, 0, 0) < 0)
          refuse(path, name + " is unreadable or truncated: " + open.error.message);
        for (std::uint32_t r = y0; r < std::min(h, y0 + tile_h); ++r)
          put(tile.data() + size_t{r - y0} * tile_w * bytes_per_value, r, x0, std::min(tile_w, w - x0));
      }
    }
  } else {
    // Rows in order: a compressed strip is decoded from its start.
    std::vector<unsigned char> row(static_cast<size_t>(TIFFScanlineSize(tiff)));
    if (row.size() < size_t{w} * bytes_per_value) refuse(path, name + ": unexpected row size");
    for (std::uint32_t r = 0; r <= last_row; ++r) {
      if (TIFFReadScanline(tiff, row.data(), r, 0) < 0)
        refuse(path, name + " is unreadable or truncated: " + open.error.message);
      put(row.data(), r, 0, w);
    }
  }
}

std::vector<long long> header_shape(const ImageHeader& header) {
  return std::vector<long long>(header.shape.begin(), header.shape.begin() + header.dimension);
}

// A raw volume's header is its layout, checked against the file's size.
ImageHeader raw_header(const std::string& path, const RawLayout& layout) {
  check_regular_file(path);
  if (layout.shape.size() != 2 && layout.shape.size() != 3)
    refuse(path, "a raw image needs Image/Shape: {nx, ny} or {nx, ny, nz}");
  if (layout.bits != 8 && layout.bits != 16) refuse(path, "a raw image holds 8 or 16-bit values");
  ImageHeader header;
  header.dimension = static_cast<int>(layout.shape.size());
  for (int d = 0; d < header.dimension; ++d) header.shape[d] = layout.shape[d];
  header.bits = layout.bits;
  const long long count = voxel_count(path, layout.shape);
  const long long bytes_per_value = layout.bits / 8;
  std::error_code size_error;
  const auto bytes = std::filesystem::file_size(path, size_error);
  if (size_error) refuse(path, size_error.message());
  if (static_cast<long long>(bytes) != count * bytes_per_value)
    refuse(path, "holds " + std::to_string(bytes) + " bytes, but Image/Shape " + shape_words(layout.shape) + " of " +
                     (layout.bits == 16 ? "uint16" : "uint8") + " needs " + std::to_string(count * bytes_per_value) +
                     (bytes < static_cast<unsigned long long>(count * bytes_per_value)
                          ? " (the file is cut short, or Image/Shape or Image/Type says too much)"
                          : " (Image/Shape or Image/Type says too little)"));
  return header;
}

// The window's rows of a raw volume, each run of consecutive voxels of a
// row by one seek and one read.
VoxelImage read_raw_window(const std::string& path, const ImageHeader& header, const ImageWindow& window) {
  VoxelImage image = detail::empty_window_image(header, window);
  const long long bytes_per_value = header.bits / 8;
  const auto runs = detail::layer_runs(window.source[0]);
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(path, std::strerror(errno));
  std::vector<unsigned char> data;
  for (long long k = 0; k < image.shape[2]; ++k)
    for (long long j = 0; j < image.shape[1]; ++j) {
      const long long row = (window.source[2][k] * header.shape[1] + window.source[1][j]) * header.shape[0];
      for (const auto& run : runs) {
        data.resize(static_cast<size_t>(run.count * bytes_per_value));
        in.seekg(static_cast<std::streamoff>((row + run.lowest_source()) * bytes_per_value));
        in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size()));
        if (!in || in.gcount() != static_cast<std::streamsize>(data.size())) refuse(path, std::strerror(errno));
        for (long long m = 0; m < run.count; ++m) {
          const long long at = run.step > 0 ? m : run.count - 1 - m;  // a reflected run backwards
          image.values[image.index(run.first + m, j, k)] =
              bytes_per_value == 2 ? static_cast<std::uint16_t>(data[2 * at] | (data[2 * at + 1] << 8)) : data[at];
        }
      }
    }
  return image;
}

enum class ImageFormat { Png, Tiff, Raw, Hdf5 };

ImageFormat format_of(const ImageSource& source) {
  const std::string ext = lower_extension(source.path);
  const ImageFormat format = ext == ".png"                      ? ImageFormat::Png
                             : ext == ".tif" || ext == ".tiff" ? ImageFormat::Tiff
                             : ext == ".raw"                   ? ImageFormat::Raw
                             : ext == ".h5" || ext == ".hdf5"  ? ImageFormat::Hdf5
                                                               : throw std::invalid_argument(
                                                                     "Image/File '" + source.path +
                                                                     "': unknown image format '" + ext +
                                                                     "': the name must end in .png, .tif, .tiff, "
                                                                     ".raw, .h5 or .hdf5");
  if (format != ImageFormat::Hdf5 && !source.dataset.empty())
    refuse(source.path, "Image/Dataset '" + source.dataset +
                            "' is given, but only an HDF5 file (.h5, .hdf5) holds datasets: leave it empty");
  return format;
}

}  // namespace

VoxelImage read_png(const std::string& path, const ImageSizeCheck& check) {
  auto png = open_png(path);
  auto& reader = png->reader;
  if (!png_prepare(reader.png, reader.info)) refuse(path, std::string("unreadable PNG: ") + png->error.message);
  VoxelImage image;
  image.dimension = 2;
  image.shape = png->header.shape;
  image.bits = png->header.bits;
  const auto width = static_cast<png_uint_32>(image.shape[0]), height = static_cast<png_uint_32>(image.shape[1]);
  const long long count = voxel_count(path, {image.shape[0], image.shape[1]});
  check_size(check, count, {image.shape[0], image.shape[1]});
  const size_t row_bytes = png_get_rowbytes(reader.png, reader.info);
  const size_t pixel_bytes = image.bits / 8;
  if (row_bytes != pixel_bytes * width) refuse(path, "unexpected PNG row size");
  std::vector<png_byte> pixels(row_bytes * height);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 r = 0; r < height; ++r) rows[r] = pixels.data() + r * row_bytes;
  if (!png_read_pixels(reader.png, reader.info, rows.data()))
    refuse(path, std::string("unreadable or truncated PNG: ") + png->error.message);

  image.values.resize(static_cast<size_t>(count));
  for (long long r = 0; r < image.shape[1]; ++r) {
    const long long j = image.shape[1] - 1 - r;  // the first row is the top of the picture: the largest y
    const png_byte* row = rows[r];
    for (long long i = 0; i < image.shape[0]; ++i)
      image.values[image.index(i, j)] =
          image.bits == 16 ? static_cast<std::uint16_t>((row[2 * i] << 8) | row[2 * i + 1])  // PNG is big-endian
                           : row[i];
  }
  return image;
}

VoxelImage read_tiff(const std::string& path, const ImageSizeCheck& check) {
  return read_image_window(ImageSource{path, {}, {}}, ImageWindow{}, check);
}

VoxelImage read_raw(const std::string& path, const RawLayout& layout, const ImageSizeCheck& check) {
  return read_image_window(ImageSource{path, layout, {}}, ImageWindow{}, check);
}

VoxelImage read_image(const std::string& path, const RawLayout& raw, const ImageSizeCheck& check) {
  return read_image(ImageSource{path, raw, {}}, check);
}

VoxelImage read_image(const ImageSource& source, const ImageSizeCheck& check) {
  if (format_of(source) == ImageFormat::Png) return read_png(source.path, check);
  return read_image_window(source, ImageWindow{}, check);
}

ImageHeader read_image_header(const ImageSource& source) {
  switch (format_of(source)) {
    case ImageFormat::Png: return open_png(source.path)->header;
    case ImageFormat::Tiff: {
      auto tiff = open_tiff(source.path);
      return tiff_header(*tiff, source.path);
    }
    case ImageFormat::Raw: return raw_header(source.path, source.raw);
    case ImageFormat::Hdf5: break;
  }
  return detail::hdf5_image_header(source.path, source.dataset);
}

VoxelImage read_image_window(const ImageSource& source, const ImageWindow& window, const ImageSizeCheck& check) {
  const std::string& path = source.path;
  const ImageFormat format = format_of(source);
  if (format == ImageFormat::Png) {
    const auto header = read_image_header(source);
    const auto resolved = detail::resolved_window(header, window, path);
    check_size(check, voxel_count(path, header_shape(header)), header_shape(header));  // decoded whole
    return take_window(read_png(path), resolved);
  }
  if (format == ImageFormat::Hdf5) return detail::read_hdf5_window(path, source.dataset, window, check);
  std::unique_ptr<OpenTiff> tiff;
  ImageHeader header;
  if (format == ImageFormat::Tiff) {
    tiff = open_tiff(path);
    header = tiff_header(*tiff, path);
  } else {
    header = raw_header(path, source.raw);
  }
  const auto resolved = detail::resolved_window(header, window, path);
  std::vector<long long> kept;
  for (int d = 0; d < header.dimension; ++d) kept.push_back(static_cast<long long>(resolved.source[d].size()));
  check_size(check, voxel_count(path, kept), header_shape(header));
  if (format == ImageFormat::Raw) return read_raw_window(path, header, resolved);
  VoxelImage image = detail::empty_window_image(header, resolved);
  for (long long k = 0; k < image.shape[2]; ++k)
    read_tiff_page(*tiff, path, header, resolved, resolved.source[2][k], k, check, image);
  return image;
}

VoxelImage take_window(const VoxelImage& image, const ImageWindow& window) {
  ImageHeader header;
  header.dimension = image.dimension;
  header.shape = image.shape;
  header.bits = image.bits;
  const auto resolved = detail::resolved_window(header, window, "(held)");
  VoxelImage out = detail::empty_window_image(header, resolved);
  for (long long k = 0; k < out.shape[2]; ++k)
    for (long long j = 0; j < out.shape[1]; ++j)
      for (long long i = 0; i < out.shape[0]; ++i)
        out.values[out.index(i, j, k)] = image.at(resolved.source[0][i], resolved.source[1][j], resolved.source[2][k]);
  return out;
}

}  // namespace poresph
