#include "scene/ImageScene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/Kernel.hpp"
#include "core/MemoryAvailable.hpp"
#include "io/Checksum.hpp"
#include "parallel/Decomposition.hpp"
#include "scene/ImagePieces.hpp"

namespace poresph {
namespace {

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument(why); }

// "{1, 2, 3}": for messages.
template <class T>
std::string list_text(const std::vector<T>& values) {
  std::ostringstream out;
  out.precision(10);
  out << "{";
  for (size_t k = 0; k < values.size(); ++k) out << (k ? ", " : "") << values[k];
  out << "}";
  return out.str();
}

// A refusal some processes found is every process's, so that none runs on
// alone into the next collective step.
template <class Step>
void on_every_process(const Communicator& comm, Step&& step) {
  std::string problem;
  try {
    step();
  } catch (const std::exception& e) {
    problem = e.what();
  }
  problem = comm.first_problem(problem);
  if (!problem.empty()) refuse(problem);
}

// How the file's voxels lie in the cell, as the request asks: doubled
// along the driven axis with Image/Mirror (checked in checked_layout).
ImageLayout image_layout(const ImageRequest& request, const ImageHeader& header, const SceneConfig& scene) {
  ImageLayout layout;
  layout.dimension = header.dimension;
  layout.file_shape = header.shape;
  layout.periodic = scene.periodic;
  int driven = 0;
  for (int d = 0; request.mirror && d < header.dimension; ++d)
    if (scene.body_force[d] != 0) layout.mirror_axis = d, ++driven;
  if (driven != 1) layout.mirror_axis = -1;
  return layout;
}

// What the file says of itself, checked against the scene: its dimension,
// the solid values its bits can hold, the mirror's axis, the cell's extent.
ImageLayout checked_layout(const ImageRequest& request, const ImageHeader& header, SceneConfig& scene) {
  const std::string& file = request.source.path;
  const std::string named = "Image/File '" + file + "' (" + shape_text(header.shape, header.dimension) + ")";
  const auto& given = request.source.raw.shape;
  if (!given.empty() && !std::equal(given.begin(), given.end(), header.shape.begin(),
                                    header.shape.begin() + header.dimension))
    refuse(named + " is not of Image/Shape " + list_text(given));
  if (header.dimension != scene.dimension)
    refuse(named + " is a " + std::to_string(header.dimension) + "D image, but Domain/Cell Size has " +
           std::to_string(scene.dimension) + " values");
  const int largest = (1 << header.bits) - 1;
  for (int v : request.solid_values)
    if (v > largest)
      refuse("Image/Solid Values: " + std::to_string(v) + " cannot occur in " + named + ", an " +
             std::to_string(header.bits) + "-bit image (values 0 to " + std::to_string(largest) + ")");
  ImageLayout layout = image_layout(request, header, scene);
  if (request.mirror) {
    if (request.tensor)
      refuse("Image/Mirror mirrors along the one driven axis, and Permeability/Tensor drives every axis in turn: "
             "use one of them");
    int axis = -1, driven = 0;
    for (int d = 0; d < scene.dimension; ++d)
      if (scene.body_force[d] != 0) axis = d, ++driven;
    if (driven != 1) refuse("Image/Mirror mirrors along the driven axis: Fluid/Body Force must lie along one axis");
    layout.mirror_axis = axis;
    scene.image.mirror_axis = axis;
  }
  // The cell is the image: a cell of another size would stretch the voxels
  // or leave a part of the cell without a solid or pore said.
  const auto cell_voxels = layout.cell_voxels();
  std::vector<double> cell, extent;
  bool agree = true;
  for (int d = 0; d < scene.dimension; ++d) {
    cell.push_back(scene.cell_size[d]);
    extent.push_back(cell_voxels[d] * request.voxel_size);
    agree = agree && std::abs(cell[d] - extent[d]) <= 1e-9 * extent[d];
  }
  if (!agree) {
    std::ostringstream msg;
    msg.precision(10);
    msg << "Domain/Cell Size " << list_text(cell) << " is not the extent of the image, " << list_text(extent) << " ("
        << shape_text(cell_voxels, scene.dimension) << " voxels" << (request.mirror ? " after Image/Mirror" : "")
        << " of Image/Voxel Size " << request.voxel_size << " m): they must agree to 1e-9 relative";
    refuse(msg.str());
  }
  return layout;
}

// This process's box of the process grid over the image's extent (the
// cell, once checked), in the cell's voxels.
template <int Dim>
VoxelBox grid_voxel_box(const SceneConfig& scene, const ImageLayout& layout, double voxel_size,
                        const Communicator& comm) {
  std::array<double, Dim> cell{};
  std::array<bool, Dim> periodic{};
  std::array<std::vector<double>, Dim> cuts;
  for (int d = 0; d < Dim; ++d)
    cell[d] = layout.cell_voxels()[d] * voxel_size, periodic[d] = scene.periodic[d], cuts[d] = scene.cuts[d];
  const auto box = grid_decomposition<Dim>(cell, periodic, comm.size(), scene.process_grid, cuts).box(comm.rank());
  return voxel_box(box.lo.data(), box.hi.data(), Dim, voxel_size, layout.cell_voxels());
}

// The memory a piece takes to make its walls, for the processes sharing
// this machine, against what it has: checked once the file has said its
// size and before any voxel is allocated, so that a header declaring far
// more voxels than the memory holds is refused with the estimate.
ImageSizeCheck piece_memory_check(const std::string& file, const SceneConfig& scene, long long halo,
                                  const Communicator& comm) {
  const int sharing = comm.on_this_machine();
  return [=](long long voxels, const std::string& shape) {
    const MemoryBudget budget = machine_memory_budget(scene.memory_limit_bytes, sharing);
    const double need = kImageSetupBytes * static_cast<double>(voxels);
    if (!(need * budget.processes_on_machine > budget.available_bytes)) return;
    // Under an address-space limit the message speaks of one process: its need against its own limit.
    AvailableMemory available{budget.available_bytes, budget.source};
    double need_here = need * budget.processes_on_machine;
    if (budget.each_process_limited) {
      available = {budget.available_bytes / budget.processes_on_machine,
                   "what is left of the process's address-space limit (ulimit -v)"};
      need_here = need;
    }
    std::ostringstream msg;
    msg.precision(3);
    msg << "Image/File '" << file << "' (" << shape << "): making its walls takes about " << need_here / 1e9
        << " GB for a moment (" << kImageSetupBytes << " bytes a voxel of each process's piece, " << voxels
        << " voxels here";
    if (sharing > 1 || comm.size() > 1)
      msg << " (its box and a halo of " << halo << "), " << sharing << " processes on this machine";
    msg << "), and " << available.bytes / 1e9 << " GB are available (" << available.source
        << "). Crop or coarsen the image, or run on more processes or machines";
    refuse(msg.str());
  };
}

// The solid and pore voxels of all the boxes.
VoxelCounts count_pieces(const ImagePiece& piece, const std::vector<char>& solid, const Communicator& comm) {
  long long counts[2] = {0, 0};
  std::array<long long, 3> c{};
  for (c[2] = piece.box.lo[2]; c[2] < piece.box.hi[2]; ++c[2])
    for (c[1] = piece.box.lo[1]; c[1] < piece.box.hi[1]; ++c[1])
      for (c[0] = piece.box.lo[0]; c[0] < piece.box.hi[0]; ++c[0])
        ++counts[solid[static_cast<size_t>(piece.index_of_cell_voxel(c))] ? 0 : 1];
  comm.sum(counts, 2);
  return VoxelCounts{counts[0], counts[1]};
}

// The values of the pore voxels that neither Image/Solid Values nor a
// phase's Image Values name, with their counts, over the boxes. More than
// one of them says that the image holds more than solid and one pore: a
// label image's grains, or 8-bit data read as 16 (Image/Type), all read as
// pore.
std::vector<std::pair<int, long long>> unnamed_pore_values(const ImagePiece& piece, const std::vector<char>& solid,
                                                           const std::vector<int>& phase_values,
                                                           const Communicator& comm) {
  std::vector<long long> count(1 << 16, 0);
  std::array<long long, 3> c{};
  for (c[2] = piece.box.lo[2]; c[2] < piece.box.hi[2]; ++c[2])
    for (c[1] = piece.box.lo[1]; c[1] < piece.box.hi[1]; ++c[1])
      for (c[0] = piece.box.lo[0]; c[0] < piece.box.hi[0]; ++c[0]) {
        const auto n = static_cast<size_t>(piece.index_of_cell_voxel(c));
        if (!solid[n]) ++count[piece.voxels.values[n]];
      }
  for (int v : phase_values)
    if (v >= 0 && v < static_cast<int>(count.size())) count[static_cast<size_t>(v)] = 0;
  comm.sum(count.data(), static_cast<int>(count.size()));
  std::vector<std::pair<int, long long>> found;
  for (size_t v = 0; v < count.size(); ++v)
    if (count[v] > 0) found.emplace_back(static_cast<int>(v), count[v]);
  return found;
}

// The checksum of the whole image's solid flags (one uint16 a voxel, its
// flat index in the cell the row), summed over the boxes.
std::uint64_t pieces_solid_checksum(const ImagePiece& piece, const std::vector<char>& solid, const Communicator& comm) {
  std::uint64_t sum = 0;
  std::array<long long, 3> c{};
  for (c[2] = piece.box.lo[2]; c[2] < piece.box.hi[2]; ++c[2])
    for (c[1] = piece.box.lo[1]; c[1] < piece.box.hi[1]; ++c[1])
      for (c[0] = piece.box.lo[0]; c[0] < piece.box.hi[0]; ++c[0]) {
        const std::uint16_t flag = solid[static_cast<size_t>(piece.index_of_cell_voxel(c))];
        sum += row_checksum(&flag, 1, 1, c[0] + piece.cell[0] * (c[1] + piece.cell[1] * c[2]));
      }
  return comm.sum_modulo(sum);
}

// face_mismatch (geometry/VoxelImage.hpp) over the pieces: each box counts
// its voxels whose phase differs from the next layer's (in its halo, or
// across the periodic face), layer by layer, summed over the boxes.
FaceMismatch pieces_face_mismatch(const ImagePiece& piece, const std::vector<char>& solid, int axis,
                                  const Communicator& comm) {
  const long long n = piece.cell[axis];
  FaceMismatch result;
  if (n < 2) return result;
  std::vector<long long> differing(static_cast<size_t>(n), 0);  // layer i against layer i + 1 (n - 1: against 0)
  std::array<long long, 3> c{};
  for (c[2] = piece.box.lo[2]; c[2] < piece.box.hi[2]; ++c[2])
    for (c[1] = piece.box.lo[1]; c[1] < piece.box.hi[1]; ++c[1])
      for (c[0] = piece.box.lo[0]; c[0] < piece.box.hi[0]; ++c[0]) {
        auto next = c;
        next[axis] = c[axis] + 1 < n ? c[axis] + 1 : (piece.wraps[axis] ? 0 : n);  // a split axis: the halo's layer n
        differing[c[axis]] += solid[static_cast<size_t>(piece.index_of_cell_voxel(c))] !=
                              solid[static_cast<size_t>(piece.index_of_cell_voxel(next))];
      }
  comm.sum(differing.data(), static_cast<int>(n));
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const double layer = static_cast<double>(piece.cell[a] * piece.cell[b]);
  result.faces = differing[n - 1] / layer;
  for (long long i = 0; i + 1 < n; ++i) result.inside = std::max(result.inside, differing[i] / layer);
  return result;
}

// A sample that is not periodic, run in a periodic cell, gains a seam of
// solid and pore at its faces that is not in the rock: said, with the remedy.
void warn_of_seams(const ImagePiece& piece, const std::vector<char>& solid, const std::string& named,
                   SceneConfig& scene, const Communicator& comm) {
  for (int axis = 0; axis < scene.dimension; ++axis) {
    if (!scene.periodic[axis]) continue;
    const auto mismatch = pieces_face_mismatch(piece, solid, axis, comm);
    if (mismatch.faces > std::max(2 * mismatch.inside, 0.05)) {
      std::ostringstream msg;
      msg.precision(3);
      msg << named << ": its two faces across " << "xyz"[axis] << " differ in " << 100 * mismatch.faces
          << " % of their voxels, where neighbouring layers inside differ in at most " << 100 * mismatch.inside
          << " %: the periodic cell joins them with a seam that is not in the sample, and k is that of the seamed "
             "cell. If the sample is not periodic along "
          << "xyz"[axis] << ", Image/Mirror makes it so along the driven axis";
      scene.warnings.push_back(msg.str());
    }
  }
}

// The halo the walls and the pore checks of every level need at a spacing.
long long halo_for(const ImageRequest& request, const SceneConfig& scene, double spacing) {
  const double coarsest = spacing * request.coarsening;
  const double shell = kSupportRadiusInH * scene.smoothing_length_ratio * coarsest;
  // The pore check's balls, 3 spacings across, placed on distances exact to their radius and a voxel more.
  const long long balls = 2 * static_cast<long long>(std::ceil(1.5 * coarsest / request.voxel_size)) + 12;
  return std::max(walls_halo(shell, request.voxel_size), balls);
}

bool driven(const ImageRequest& request, const SceneConfig& scene, int axis) {
  return request.tensor || scene.body_force[axis] != 0;
}

}  // namespace

void build_image_scene(const ImageRequest& request, SceneConfig& scene, const Communicator& comm) {
  const std::string& file = request.source.path;
  // Every process reads the header; a file is the same file for all of them.
  const ImageHeader header = read_image_header(request.source);
  const std::string named = "Image/File '" + file + "' (" + shape_text(header.shape, header.dimension) + ")";
  // The halo follows from the spacing; where the spacing follows from the
  // bottleneck (Spacings Across Throat), or a bottleneck is wider than the
  // halo holds exactly, the pieces are made again with the halo they need.
  long long halo = halo_for(request, scene, request.coarsest_spacing > 0 ? request.coarsest_spacing / request.coarsening
                                                                          : request.voxel_size);
  // The size the header declares goes to the memory check first, before the
  // rest of the scene is held against the image: an image too large is
  // refused for what it is, whatever else is wrong.
  VoxelBox box;
  if (header.dimension == scene.dimension) {
    const ImageLayout asked = image_layout(request, header, scene);
    on_every_process(comm, [&] {
      box = header.dimension == 2 ? grid_voxel_box<2>(scene, asked, request.voxel_size, comm)
                                  : grid_voxel_box<3>(scene, asked, request.voxel_size, comm);
      ImagePiece piece;
      const ImageWindow window = piece_window(asked, box, halo, piece);
      long long voxels = 1;
      for (const auto& layers : window.source) voxels *= static_cast<long long>(layers.size());
      piece_memory_check(file, scene, halo, comm)(voxels, shape_text(header.shape, header.dimension));
    });
  }
  const ImageLayout layout = checked_layout(request, header, scene);
  const auto solid_value = solid_value_table(request.solid_values);
  for (;;) {
    ImagePiece piece;
    on_every_process(comm, [&] {
      piece = read_image_piece(request.source, layout, box, halo, piece_memory_check(file, scene, halo, comm));
    });
    std::vector<char> solid(piece.voxels.values.size());
    for (size_t n = 0; n < solid.size(); ++n) solid[n] = solid_value[piece.voxels.values[n]];
    scene.image.counts = count_pieces(piece, solid, comm);
    if (scene.image.counts.solid == 0)
      refuse(named + " has no solid voxels: no value of Image/Solid Values " + list_text(request.solid_values) +
             " occurs in it");
    if (scene.image.counts.pore == 0)
      refuse(named + " has no pore voxels: every value is one of Image/Solid Values " +
             list_text(request.solid_values));
    const size_t warnings = scene.warnings.size();
    const auto unnamed = unnamed_pore_values(piece, solid, request.phase_values, comm);
    if (unnamed.size() > 1) {
      std::ostringstream msg;
      msg << named << " holds " << unnamed.size() << " values that Image/Solid Values "
          << list_text(request.solid_values) << " does not name (value: voxels";
      for (size_t k = 0; k < unnamed.size() && k < 8; ++k)
        msg << (k ? ", " : " ") << unnamed[k].first << ": " << unnamed[k].second;
      msg << (unnamed.size() > 8 ? ", ...)" : ")")
          << ", all read as pore: name the solid ones, or check Image/Type if the values look wrong";
      scene.warnings.push_back(msg.str());
    }
    warn_of_seams(piece, solid, named, scene, comm);
    // Every driven axis (each in turn for the tensor) needs a pore path
    // across the cell, or the run would spend its steps finding k = 0.
    std::vector<char> pore(solid.size());
    for (size_t n = 0; n < solid.size(); ++n) pore[n] = !solid[n];
    for (int axis = 0; axis < scene.dimension; ++axis)
      if (driven(request, scene, axis) && !pieces_percolate(piece, pore, axis, scene.periodic, comm))
        refuse(named + ": no pore path crosses the cell along " + std::string(1, "xyz"[axis]) +
               (request.tensor ? " (Permeability/Tensor drives every axis)" : ", the driven axis") +
               ": its pore voxels, joined across voxel faces, hold no path through the cell that way, so no flow "
               "gets through. Check Image/Solid Values " + list_text(request.solid_values));
    const std::uint64_t checksum = pieces_solid_checksum(piece, solid, comm);
    // The flags go before the distance is made, which needs kImageSetupBytes a voxel itself.
    std::vector<char>().swap(solid);
    std::vector<char>().swap(pore);
    // The walls the fluid sees: the distance to a surface found between the
    // voxels, and the driven axes' bottlenecks measured on it (a gap of one
    // voxel, open in the voxels, may close between the walls).
    auto distance = piece_surface_distance(piece, request.solid_values, request.voxel_size);
    bool whole = true;
    for (int d = 0; d < scene.dimension; ++d) whole = whole && piece.wraps[d];
    const double trusted = whole ? std::numeric_limits<double>::infinity()
                                 : piece_trusted_distance(halo, request.voxel_size);
    bool wider_than_held = false;
    double narrowest = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < scene.dimension; ++axis) {
      if (!driven(request, scene, axis)) continue;
      const double width = pieces_widest_path_width(piece, distance, axis, scene.periodic, trusted, comm);
      if (!(width > 0))
        refuse(named + ": its pore voxels cross the cell along " + std::string(1, "xyz"[axis]) +
               " only through gaps about a voxel wide, which close when the walls are placed between the voxels: "
               "no pore path is left that way. Use an image of finer voxels");
      wider_than_held = wider_than_held || width >= 2 * static_cast<double>(static_cast<float>(trusted));
      scene.image.bottleneck[axis] = width;
      narrowest = std::min(narrowest, width);
    }
    long long needed = halo;
    if (wider_than_held) needed = 2 * halo;
    if (request.coarsest_spacing == 0 && request.spacings_across_throat > 0)
      needed = std::max(needed, halo_for(request, scene, narrowest / request.spacings_across_throat));
    if (needed > halo) {
      halo = needed;
      scene.warnings.resize(warnings);
      continue;
    }
    scene.image.distance = std::make_shared<const std::vector<float>>(std::move(distance));
    scene.image.voxels = std::make_shared<const VoxelImage>(std::move(piece.voxels));
    scene.image.piece_first = piece.first;
    scene.image.piece_wraps = piece.wraps;
    scene.image.owned = piece.box;
    scene.image.cell_voxels = piece.cell;
    scene.image.solid_checksum = checksum;
    break;
  }
  scene.image.file = file;
  scene.image.voxel_size = request.voxel_size;
  scene.image.solid_values = request.solid_values;
}

}  // namespace poresph
