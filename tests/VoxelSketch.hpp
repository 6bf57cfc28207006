#pragma once
// A small 2D voxel image drawn in the test's text: rows of characters, top
// row first as displayed (y up), '#' solid (value 1), '.' pore (value 0).
#include <cstring>
#include <initializer_list>

#include "geometry/VoxelImage.hpp"

namespace poresph::testing {

inline VoxelImage sketch(std::initializer_list<const char*> rows) {
  VoxelImage image;
  image.shape = {static_cast<long long>(std::strlen(*rows.begin())), static_cast<long long>(rows.size()), 1};
  image.values.resize(static_cast<size_t>(image.count()));
  long long r = 0;
  for (const char* row : rows) {
    for (long long i = 0; i < image.shape[0]; ++i)
      image.values[image.index(i, image.shape[1] - 1 - r)] = row[i] == '#' ? 1 : 0;
    ++r;
  }
  return image;
}

}  // namespace poresph::testing
