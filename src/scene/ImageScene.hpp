#pragma once
// A segmented image made into the scene's solid: the file checked against
// the scene, each process's piece read (its box of the process grid and a
// halo, scene/ImagePieces.hpp), and the image's checks made over all the
// pieces together: the memory a piece needs, the voxel counts, the faces of
// a periodic cell, a pore path along every driven axis, the distance to the
// surface and the driven axes' bottlenecks. io/ reads the parameters and the
// files; this builds.
#include <string>
#include <vector>

#include "io/ImageReader.hpp"
#include "parallel/Communicator.hpp"
#include "scene/SceneConfig.hpp"

namespace poresph {

// What the Image sublist and the ladder ask of the image, checked one by one.
struct ImageRequest {
  // The path resolved against the scene's folder; raw.shape is Image/Shape,
  // which a file that says its own shape must match where it is given.
  ImageSource source;
  std::vector<int> solid_values;
  // Pore values given a meaning of their own (Phases/Phase 1/Image Values):
  // not the plain pore's.
  std::vector<int> phase_values;
  double voxel_size = 0;
  bool mirror = false;
  bool tensor = false;             // Permeability/Tensor: every axis is driven
  // The spacing of the coarsest level of the ladder (m), whose boundary
  // layer is the deepest: the halo must hold it. 0: not known before the
  // bottleneck is (Discretization/Spacings Across Throat).
  double coarsest_spacing = 0;
  double spacings_across_throat = 0;  // with coarsest_spacing 0
  double coarsening = 1;              // the coarsest level's spacing over the finest's
};

// Bytes a voxel of a piece that making its walls holds at its peak: the
// voxels (2), the blurred indicator (8), the surface points' index (8), the
// feature transform (8) and its distances (8), the field (4), and the
// widths measured on it after (8 + 8 + 1 + 4 as the others are freed).
constexpr double kImageSetupBytes = 40;

// Fills scene.image (and its warnings) from the request, or throws
// std::invalid_argument naming the file and what is wrong, on every process
// alike. Needs scene's dimension, cell, periodic axes, body force, memory
// limit, smoothing length ratio and process grid. Collective over comm.
void build_image_scene(const ImageRequest& request, SceneConfig& scene, const Communicator& comm = Communicator());

}  // namespace poresph
