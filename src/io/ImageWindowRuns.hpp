#pragma once
// Plumbing of the image readers (io/ImageReader.hpp): a window checked
// against the file's shape, and cut into runs of consecutive layers, each
// read by one seek or one hyperslab.
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/ImageReader.hpp"

namespace poresph::detail {

// The window with every axis spelt out (an empty one: all layers in order;
// z of a 2D image: its one layer), refused where a layer is not in the file.
inline ImageWindow resolved_window(const ImageHeader& header, const ImageWindow& window, const std::string& path) {
  ImageWindow out = window;
  for (int d = 0; d < 3; ++d) {
    auto& layers = out.source[d];
    if (layers.empty())
      for (long long n = 0; n < header.shape[d]; ++n) layers.push_back(n);
    for (long long n : layers)
      if (n < 0 || n >= header.shape[d])
        throw std::invalid_argument("Image/File '" + path + "': layer " + std::to_string(n) + " along " + "xyz"[d] +
                                    " asked for, the image has " + std::to_string(header.shape[d]));
  }
  return out;
}

// Window layers first .. first + count - 1 come from file layers
// source, source + step, ... (step +1 or -1: a reflected run).
struct LayerRun {
  long long first = 0, count = 0, source = 0;
  int step = 1;
  long long lowest_source() const { return step > 0 ? source : source - (count - 1); }
};

inline std::vector<LayerRun> layer_runs(const std::vector<long long>& layers) {
  std::vector<LayerRun> runs;
  for (long long w = 0; w < static_cast<long long>(layers.size()); ++w) {
    if (!runs.empty()) {
      LayerRun& run = runs.back();
      const long long from = layers[w] - run.source;
      if (run.count == 1 && (from == 1 || from == -1)) run.step = static_cast<int>(from);
      if (from == run.step * run.count) {
        ++run.count;
        continue;
      }
    }
    runs.push_back(LayerRun{w, 1, layers[w], 1});
  }
  return runs;
}

inline VoxelImage empty_window_image(const ImageHeader& header, const ImageWindow& window) {
  VoxelImage image;
  image.dimension = header.dimension;
  image.bits = header.bits;
  for (int d = 0; d < 3; ++d) image.shape[d] = static_cast<long long>(window.source[d].size());
  image.values.assign(static_cast<size_t>(image.count()), 0);
  return image;
}

// The HDF5 reader (io/Hdf5Image.cpp).
ImageHeader hdf5_image_header(const std::string& path, const std::string& dataset);
VoxelImage read_hdf5_window(const std::string& path, const std::string& dataset, const ImageWindow& window,
                            const ImageSizeCheck& check);

}  // namespace poresph::detail
