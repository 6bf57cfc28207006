// Segmented images from HDF5 datasets, the format micro-CT pipelines write:
// each process opens the file on its own (no MPI-IO: the pieces differ)
// and reads its window by hyperslabs, one z layer at a time.
#include <hdf5.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/Hdf5File.hpp"
#include "io/ImageReader.hpp"
#include "io/ImageWindowRuns.hpp"

namespace poresph::detail {
namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw std::invalid_argument("Image/File '" + path + "': " + why);
}

// An HDF5 identifier closed when it goes out of scope.
struct Handle {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~Handle() {
    if (id >= 0) close(id);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
};

// The datasets of a file, for a message that says what could have been meant (the first few).
std::string datasets_in(hid_t file) {
  std::vector<std::string> names;
  const H5L_iterate_t collect = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    auto& found = *static_cast<std::vector<std::string>*>(data);
    const Handle object(H5Oopen(group, name, H5P_DEFAULT), H5Oclose);
    if (object.id >= 0 && H5Iget_type(object.id) == H5I_DATASET) found.push_back(std::string("/") + name);
    return found.size() >= 8;
  };
  H5Lvisit(file, H5_INDEX_NAME, H5_ITER_INC, collect, &names);
  if (names.empty()) return "it holds no dataset";
  std::string text = "it holds ";
  for (size_t n = 0; n < names.size(); ++n) text += (n ? ", '" : "'") + names[n] + "'";
  return text + (names.size() >= 8 ? ", ..." : "");
}

// A dataset of the file open for reading, with what it says of itself.
struct OpenDataset {
  Handle file{-1, H5Fclose};
  Handle dataset{-1, H5Dclose};
  ImageHeader header;
  bool is_signed = false;
};

// Every step of `name` must be a link that exists, and its end a dataset:
// H5Dopen on a missing path only says that something failed.
void open_dataset(const std::string& path, const std::string& name, OpenDataset& open) {
  if (name.empty())
    refuse(path, "an HDF5 image needs Image/Dataset, the dataset's path inside the file; " + datasets_in(open.file.id));
  std::string prefix;
  size_t from = name[0] == '/' ? 1 : 0;
  while (from <= name.size()) {
    const size_t slash = std::min(name.find('/', from), name.size());
    prefix = name.substr(0, slash);
    if (slash > from && H5Lexists(open.file.id, prefix.c_str(), H5P_DEFAULT) <= 0)
      refuse(path, "Image/Dataset '" + name + "' is not in the file ('" + prefix + "' is missing); " +
                       datasets_in(open.file.id));
    from = slash + 1;
  }
  const Handle object(H5Oopen(open.file.id, name.c_str(), H5P_DEFAULT), H5Oclose);
  if (object.id < 0 || H5Iget_type(object.id) != H5I_DATASET)
    refuse(path, "Image/Dataset '" + name + "' is a group, not a dataset; " + datasets_in(open.file.id));
  open.dataset.id = H5Dopen2(open.file.id, name.c_str(), H5P_DEFAULT);
  if (open.dataset.id < 0) refuse(path, "Image/Dataset '" + name + "' cannot be opened");
}

void open_image(const std::string& path, const std::string& name, OpenDataset& open) {
  if (const std::string problem = hdf5_file_problem(path); !problem.empty()) refuse(path, problem);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported as exceptions
  open.file.id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (open.file.id < 0) refuse(path, "HDF5 cannot open it");
  open_dataset(path, name, open);
  const std::string named = "Image/Dataset '" + name + "'";
  const Handle type(H5Dget_type(open.dataset.id), H5Tclose);
  const H5T_class_t kind = H5Tget_class(type.id);
  if (kind != H5T_INTEGER)
    refuse(path, named + " holds " +
                     (kind == H5T_FLOAT    ? std::string("floating-point values")
                      : kind == H5T_STRING ? std::string("strings")
                                           : "values of HDF5 type class " + std::to_string(static_cast<int>(kind))) +
                     "; a segmented image holds integer labels (uint8, uint16, int32, ...)");
  open.is_signed = H5Tget_sign(type.id) == H5T_SGN_2;
  // Unsigned bytes keep 8 bits; wider or signed labels are read as 16 bits, each checked to fit.
  open.header.bits = H5Tget_size(type.id) == 1 && !open.is_signed ? 8 : 16;
  const Handle space(H5Dget_space(open.dataset.id), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank != 2 && rank != 3)
    refuse(path, named + " has " + std::to_string(rank) +
                     " dimensions; an image is [y][x] (2D) or [z][y][x] (3D), x fastest");
  hsize_t dims[3] = {1, 1, 1};
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  open.header.dimension = rank;
  for (int d = 0; d < rank; ++d) open.header.shape[d] = static_cast<long long>(dims[rank - 1 - d]);
  for (int d = 0; d < rank; ++d)
    if (open.header.shape[d] < 1) refuse(path, named + ": every side of the image must hold at least one voxel");
}

}  // namespace

ImageHeader hdf5_image_header(const std::string& path, const std::string& dataset) {
  OpenDataset open;
  open_image(path, dataset, open);
  return open.header;
}

VoxelImage read_hdf5_window(const std::string& path, const std::string& dataset, const ImageWindow& window,
                            const ImageSizeCheck& check) {
  OpenDataset open;
  open_image(path, dataset, open);
  const ImageHeader& header = open.header;
  const ImageWindow resolved = resolved_window(header, window, path);
  if (check) {
    long long kept = 1;
    std::string shape;
    for (int d = 0; d < header.dimension; ++d) {
      kept *= static_cast<long long>(resolved.source[d].size());
      shape += (d ? " x " : "") + std::to_string(header.shape[d]);
    }
    check(kept, shape);
  }
  VoxelImage image = empty_window_image(header, resolved);
  const auto x_runs = layer_runs(resolved.source[0]), y_runs = layer_runs(resolved.source[1]);
  const int rank = header.dimension;
  const Handle file_space(H5Dget_space(open.dataset.id), H5Sclose);
  std::vector<long long> block;
  for (long long k = 0; k < image.shape[2]; ++k)
    for (const auto& ry : y_runs)
      for (const auto& rx : x_runs) {
        // [z][y][x] in the file: the block of this z layer, y run and x run.
        const hsize_t start3[3] = {static_cast<hsize_t>(resolved.source[2][k]),
                                   static_cast<hsize_t>(ry.lowest_source()), static_cast<hsize_t>(rx.lowest_source())};
        const hsize_t count3[3] = {1, static_cast<hsize_t>(ry.count), static_cast<hsize_t>(rx.count)};
        const hsize_t* start = rank == 3 ? start3 : start3 + 1;
        const hsize_t* count = rank == 3 ? count3 : count3 + 1;
        block.resize(static_cast<size_t>(ry.count * rx.count));
        const Handle memory(H5Screate_simple(rank, count, nullptr), H5Sclose);
        if (H5Sselect_hyperslab(file_space.id, H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
            H5Dread(open.dataset.id, H5T_NATIVE_LLONG, memory.id, file_space.id, H5P_DEFAULT, block.data()) < 0)
          refuse(path, "Image/Dataset '" + dataset + "' is unreadable (damaged or truncated)");
        for (long long b = 0; b < ry.count; ++b)
          for (long long a = 0; a < rx.count; ++a) {
            const long long value = block[static_cast<size_t>(b * rx.count + a)];
            const long long i = rx.first + (rx.step > 0 ? a : rx.count - 1 - a);
            const long long j = ry.first + (ry.step > 0 ? b : ry.count - 1 - b);
            if (value < 0 || value > 65535)
              refuse(path, "Image/Dataset '" + dataset + "' holds the label " + std::to_string(value) +
                               " at voxel (" + std::to_string(resolved.source[0][i]) + ", " +
                               std::to_string(resolved.source[1][j]) + ", " + std::to_string(resolved.source[2][k]) +
                               "); PoreSPH reads labels 0 to 65535");
            image.values[image.index(i, j, k)] = static_cast<std::uint16_t>(value);
          }
      }
  return image;
}

}  // namespace poresph::detail

namespace poresph {

VoxelImage read_hdf5(const std::string& path, const std::string& dataset, const ImageSizeCheck& check) {
  return detail::read_hdf5_window(path, dataset, ImageWindow{}, check);
}

}  // namespace poresph
