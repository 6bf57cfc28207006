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

}  // namespace

VoxelImage read_png(const std::string& path, const ImageSizeCheck& check) {
  check_regular_file(path);
  File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) refuse(path, std::strerror(errno));
  png_byte signature[8];
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    refuse(path, "not a PNG file (it does not start with the PNG signature)");
  PngError error;
  PngReadStruct reader;
  reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, png_error_handler, png_warning_handler);
  if (!reader.png) refuse(path, "libpng could not start reading");
  reader.info = png_create_info_struct(reader.png);
  if (!reader.info) refuse(path, "libpng could not start reading");
  if (!png_read_header(reader.png, reader.info, file.get()))
    refuse(path, std::string("unreadable PNG: ") + error.message);

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
  if (!png_prepare(reader.png, reader.info)) refuse(path, std::string("unreadable PNG: ") + error.message);

  VoxelImage image;
  image.dimension = 2;
  image.shape = {{static_cast<long long>(width), static_cast<long long>(height), 1}};
  image.bits = depth == 16 ? 16 : 8;
  const long long count = voxel_count(path, {image.shape[0], image.shape[1]});
  check_size(check, count, {image.shape[0], image.shape[1]});
  const size_t row_bytes = png_get_rowbytes(reader.png, reader.info);
  const size_t pixel_bytes = image.bits / 8;
  if (row_bytes != pixel_bytes * width) refuse(path, "unexpected PNG row size");
  std::vector<png_byte> pixels(row_bytes * height);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 r = 0; r < height; ++r) rows[r] = pixels.data() + r * row_bytes;
  if (!png_read_pixels(reader.png, reader.info, rows.data()))
    refuse(path, std::string("unreadable or truncated PNG: ") + error.message);

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
  check_regular_file(path);
  TiffError error;
  std::unique_ptr<TIFFOpenOptions, void (*)(TIFFOpenOptions*)> options(TIFFOpenOptionsAlloc(), &TIFFOpenOptionsFree);
  if (!options) refuse(path, "libtiff could not start reading");
  TIFFOpenOptionsSetErrorHandlerExtR(options.get(), tiff_error_handler, &error);
  TIFFOpenOptionsSetWarningHandlerExtR(options.get(), tiff_warning_handler, nullptr);
  std::unique_ptr<TIFF, void (*)(TIFF*)> tiff(TIFFOpenExt(path.c_str(), "r", options.get()), &TIFFClose);
  if (!tiff) refuse(path, std::string("unreadable TIFF: ") + error.message);

  VoxelImage image;
  // The pages' count, from the chain of their headers, so that the whole
  // volume's size is checked before any of it is allocated.
  const long long page_count = std::max<long long>(1, TIFFNumberOfDirectories(tiff.get()));
  long long pages = 0;
  std::uint32_t width = 0, height = 0;
  std::uint16_t bits = 0;
  do {
    const std::string page = "page " + std::to_string(pages + 1);
    std::uint32_t w = 0, h = 0;
    std::uint16_t samples = 1, b = 1, format = SAMPLEFORMAT_UINT, photometric = PHOTOMETRIC_MINISBLACK;
    if (!TIFFGetField(tiff.get(), TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(tiff.get(), TIFFTAG_IMAGELENGTH, &h))
      refuse(path, page + " has no width or height");
    TIFFGetFieldDefaulted(tiff.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
    TIFFGetFieldDefaulted(tiff.get(), TIFFTAG_BITSPERSAMPLE, &b);
    TIFFGetFieldDefaulted(tiff.get(), TIFFTAG_SAMPLEFORMAT, &format);
    TIFFGetField(tiff.get(), TIFFTAG_PHOTOMETRIC, &photometric);  // absent: read as grey
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
    if (pages == 0) {
      const std::vector<long long> shape = page_count > 1 ? std::vector<long long>{w, h, page_count}
                                                          : std::vector<long long>{w, h};
      check_size(check, voxel_count(path, shape), shape);
    }
    const long long per_page = voxel_count(path, {w, h, pages + 1}) / (pages + 1);
    image.values.resize(static_cast<size_t>(per_page * (pages + 1)));
    image.shape = {{static_cast<long long>(w), static_cast<long long>(h), pages + 1}};
    // One stored row (or tile row) into the image: row r is y = h - 1 - r.
    const size_t bytes_per_value = b / 8;
    auto put = [&](const unsigned char* data, std::uint32_t r, std::uint32_t first, std::uint32_t n) {
      const long long j = static_cast<long long>(h) - 1 - r;
      for (std::uint32_t m = 0; m < n; ++m) {
        std::uint16_t v = data[m];
        if (bytes_per_value == 2) std::memcpy(&v, data + 2 * m, 2);  // libtiff gives native byte order
        image.values[image.index(first + m, j, pages)] = v;
      }
    };
    if (TIFFIsTiled(tiff.get())) {
      std::uint32_t tile_w = 0, tile_h = 0;
      TIFFGetField(tiff.get(), TIFFTAG_TILEWIDTH, &tile_w);
      TIFFGetField(tiff.get(), TIFFTAG_TILELENGTH, &tile_h);
      if (tile_w == 0 || tile_h == 0) refuse(path, page + " is tiled with tiles of no size");
      // A tile is allocated whole: one declared far larger than the page is checked too.
      if (static_cast<long long>(tile_w) * tile_h > static_cast<long long>(w) * h)
        check_size(check, voxel_count(path, {tile_w, tile_h}), {tile_w, tile_h});
      std::vector<unsigned char> tile(static_cast<size_t>(TIFFTileSize(tiff.get())));
      if (tile.size() < size_t{tile_w} * tile_h * bytes_per_value) refuse(path, page + ": unexpected tile size");
      for (std::uint32_t y0 = 0; y0 < h; y0 += tile_h)
        for (std::uint32_t x0 = 0; x0 < w; x0 += tile_w) {
          if (TIFFReadTile(tiff.get(), tile.data(), x0, y0, 0, 0) < 0)
            refuse(path, page + " is unreadable or truncated: " + error.message);
          for (std::uint32_t r = y0; r < std::min(h, y0 + tile_h); ++r)
            put(tile.data() + size_t{r - y0} * tile_w * bytes_per_value, r, x0, std::min(tile_w, w - x0));
        }
    } else {
      std::vector<unsigned char> row(static_cast<size_t>(TIFFScanlineSize(tiff.get())));
      if (row.size() < size_t{w} * bytes_per_value) refuse(path, page + ": unexpected row size");
      for (std::uint32_t r = 0; r < h; ++r) {
        if (TIFFReadScanline(tiff.get(), row.data(), r, 0) < 0)
          refuse(path, page + " is unreadable or truncated: " + error.message);
        put(row.data(), r, 0, w);
      }
    }
    ++pages;
  } while (TIFFReadDirectory(tiff.get()));
  // TIFFReadDirectory says 0 at the last page and on a damaged one alike; only the latter leaves a message.
  if (error.message[0] != '\0')
    refuse(path, "page " + std::to_string(pages + 1) + " is unreadable: " + error.message);
  image.dimension = pages > 1 ? 3 : 2;
  image.bits = bits;
  return image;
}

VoxelImage read_raw(const std::string& path, const RawLayout& layout, const ImageSizeCheck& check) {
  check_regular_file(path);
  if (layout.shape.size() != 2 && layout.shape.size() != 3)
    refuse(path, "a raw image needs Image/Shape: {nx, ny} or {nx, ny, nz}");
  if (layout.bits != 8 && layout.bits != 16) refuse(path, "a raw image holds 8 or 16-bit values");
  VoxelImage image;
  image.dimension = static_cast<int>(layout.shape.size());
  for (int d = 0; d < image.dimension; ++d) image.shape[d] = layout.shape[d];
  image.bits = layout.bits;
  const long long count = voxel_count(path, layout.shape);
  const long long bytes_per_value = layout.bits / 8;
  std::error_code size_error;
  const auto bytes = std::filesystem::file_size(path, size_error);
  if (size_error) refuse(path, size_error.message());
  if (static_cast<long long>(bytes) != count * bytes_per_value)
    refuse(path, "holds " + std::to_string(bytes) + " bytes, but Image/Shape " + shape_text(image) + " of " +
                     (layout.bits == 16 ? "uint16" : "uint8") + " needs " + std::to_string(count * bytes_per_value) +
                     (bytes < static_cast<unsigned long long>(count * bytes_per_value)
                          ? " (the file is cut short, or Image/Shape or Image/Type says too much)"
                          : " (Image/Shape or Image/Type says too little)"));
  check_size(check, count, layout.shape);
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> data(static_cast<size_t>(count * bytes_per_value));
  in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size()));
  if (!in || in.gcount() != static_cast<std::streamsize>(data.size())) refuse(path, std::strerror(errno));
  image.values.resize(static_cast<size_t>(count));
  for (long long n = 0; n < count; ++n)
    image.values[n] = bytes_per_value == 2 ? static_cast<std::uint16_t>(data[2 * n] | (data[2 * n + 1] << 8))
                                           : data[n];
  return image;
}

VoxelImage read_image(const std::string& path, const RawLayout& raw, const ImageSizeCheck& check) {
  const std::string ext = lower_extension(path);
  if (ext == ".png") return read_png(path, check);
  if (ext == ".tif" || ext == ".tiff") return read_tiff(path, check);
  if (ext == ".raw") return read_raw(path, raw, check);
  refuse(path, "unknown image format '" + ext + "': the name must end in .png, .tif, .tiff or .raw");
}

}  // namespace poresph
