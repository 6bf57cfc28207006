#include "scene/ImagePieces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "geometry/DistanceField.hpp"
#include "geometry/DistanceTransform.hpp"

namespace poresph {
namespace {

// Read from a point: the interpolation's voxel and the normal's step.
constexpr long long kReach = static_cast<long long>(DistanceField<3, Kokkos::HostSpace>::kNormalStep) + 1;
// A voxel's value is exact when its nearest surface voxel lies this much
// inside the piece: the surface points of a voxel depend on the voxels
// within 4 of it (two blurs, the gradient, the crossing's neighbour), and
// the nearest point is searched among the voxels next to the nearest site.
constexpr long long kSurfaceDependence = 7;
// A surface voxel lies within 2 voxels of the surface point it carries.
constexpr long long kSiteToSurface = 2;

long long wrapped(long long c, long long n) { return (c % n + n) % n; }

// The window of cell layers [lo, hi) along each axis, as layers of a
// source of shape `source_shape` (the file's, reflected along
// `mirror_axis`, or the cell's own).
ImageWindow window_of_layers(const ImagePiece& piece, const std::array<long long, 3>& lo,
                             const std::array<long long, 3>& hi, const std::array<long long, 3>& source_shape,
                             int mirror_axis) {
  ImageWindow window;
  for (int d = 0; d < 3; ++d)
    for (long long c = lo[d]; c < hi[d]; ++c) {
      long long layer = wrapped(c, piece.cell[d]);
      if (d == mirror_axis && layer >= source_shape[d]) layer = 2 * source_shape[d] - 1 - layer;
      window.source[d].push_back(layer);
    }
  return window;
}

// The cell layers a piece holds along each axis: the box, widened by the
// halo where the box is not the whole axis (and cut at a bounded axis's ends).
void piece_layers(const ImageLayout& layout, const VoxelBox& box, long long halo, ImagePiece& piece,
                  std::array<long long, 3>& lo, std::array<long long, 3>& hi) {
  piece.cell = layout.cell_voxels();
  piece.box = box;
  piece.dimension = layout.dimension;
  for (int d = 0; d < 3; ++d) {
    const long long n = piece.cell[d];
    if (box.lo[d] < 0 || box.hi[d] > n || box.lo[d] > box.hi[d])
      throw std::invalid_argument("image piece: the box is not inside the cell's voxels");
    const bool whole = d >= layout.dimension || (box.lo[d] == 0 && box.hi[d] == n);
    lo[d] = whole ? 0 : box.lo[d] - halo;
    hi[d] = whole ? n : box.hi[d] + halo;
    if (!layout.periodic[d] || d >= layout.dimension) lo[d] = std::max(lo[d], 0LL), hi[d] = std::min(hi[d], n);
    piece.first[d] = lo[d];
    piece.wraps[d] = whole && d < layout.dimension && layout.periodic[d];
    piece.periodic[d] = layout.periodic[d];
  }
}

// The box's voxels in the piece's frame: first and count along each axis.
struct BoxInPiece {
  std::array<long long, 3> first{}, count{};
  long long total = 1;
};
BoxInPiece box_in_piece(const ImagePiece& piece) {
  BoxInPiece b;
  for (int d = 0; d < 3; ++d) {
    b.first[d] = piece.box.lo[d] - piece.first[d];
    b.count[d] = piece.box.hi[d] - piece.box.lo[d];
    b.total *= b.count[d];
  }
  return b;
}

// The open voxels of the box joined across faces inside it: a label a
// voxel (-1: closed), 0 .. labels - 1.
struct BoxLabels {
  std::vector<int> label;
  int labels = 0;
};
BoxLabels label_box(const ImagePiece& piece, const BoxInPiece& b, const std::vector<char>& open) {
  BoxLabels out;
  out.label.assign(static_cast<size_t>(b.total), -1);
  const auto& shape = piece.voxels.shape;
  auto piece_index = [&](const long long (&c)[3]) {
    return static_cast<size_t>((b.first[0] + c[0]) + shape[0] * ((b.first[1] + c[1]) + shape[1] * (b.first[2] + c[2])));
  };
  auto coordinates = [&](long long n, long long (&c)[3]) {
    c[0] = n % b.count[0];
    c[1] = n / b.count[0] % b.count[1];
    c[2] = n / (b.count[0] * b.count[1]);
  };
  const std::array<long long, 3> stride{{1, b.count[0], b.count[0] * b.count[1]}};
  std::vector<long long> stack;
  for (long long seed = 0; seed < b.total; ++seed) {
    long long c[3];
    coordinates(seed, c);
    if (out.label[seed] >= 0 || !open[piece_index(c)]) continue;
    const int label = out.labels++;
    out.label[seed] = label;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const long long n = stack.back();
      stack.pop_back();
      coordinates(n, c);
      for (int d = 0; d < piece.dimension; ++d)
        for (int step : {-1, 1}) {
          const long long e = c[d] + step;
          if (e < 0 || e >= b.count[d]) continue;  // the box's faces: joined across on rank 0
          const long long m = n + step * stride[d];
          long long mc[3] = {c[0], c[1], c[2]};
          mc[d] = e;
          if (out.label[m] >= 0 || !open[piece_index(mc)]) continue;
          out.label[m] = label;
          stack.push_back(m);
        }
    }
  }
  return out;
}

// Labels joined with the laps they lie apart along the driven axis: a
// union-find whose every member knows its lap relative to its root. Two
// voxels joined on two different laps are one voxel and its periodic
// image joined: the path along the axis.
class LapUnion {
 public:
  explicit LapUnion(long long n) : parent_(static_cast<size_t>(n)), lap_(static_cast<size_t>(n), 0) {
    for (long long k = 0; k < n; ++k) parent_[k] = k;
  }
  // The root of a, with a's lap relative to it.
  long long find(long long a, long long& lap) {
    lap = 0;
    long long root = a;
    while (parent_[root] != root) lap += lap_[root], root = parent_[root];
    // Path compression: every member on the way points at the root with its lap.
    long long rest = lap;
    while (parent_[a] != a) {
      const long long next = parent_[a], step = lap_[a];
      parent_[a] = root, lap_[a] = rest;
      rest -= step, a = next;
    }
    return root;
  }
  // Joins b, lying `laps` laps beyond a; false when they were joined already at another lap.
  bool join(long long a, long long b, long long laps) {
    long long lap_a = 0, lap_b = 0;
    const long long root_a = find(a, lap_a), root_b = find(b, lap_b);
    if (root_a == root_b) return lap_b - lap_a == laps;
    parent_[root_b] = root_a;
    lap_[root_b] = lap_a + laps - lap_b;
    return true;
  }

 private:
  std::vector<long long> parent_, lap_;
};

// On rank 0: the boxes' labels joined across their faces. `faces` holds
// (cell voxel, label) of every open voxel on a box's face, `crossings`
// (label, cell voxel beyond the face, laps crossed), `ends` the labels
// that touch a bounded axis's low end (0) and high end (1).
bool joined_labels_percolate(long long labels, const std::vector<long long>& faces,
                             const std::vector<long long>& crossings, const std::vector<long long>& ends,
                             bool periodic_axis) {
  std::unordered_map<long long, long long> label_of;
  label_of.reserve(faces.size() / 2);
  for (size_t k = 0; k + 1 < faces.size(); k += 2) label_of.emplace(faces[k], faces[k + 1]);
  LapUnion joined(labels);
  for (size_t k = 0; k + 2 < crossings.size(); k += 3) {
    const auto beyond = label_of.find(crossings[k + 1]);
    if (beyond == label_of.end()) continue;  // closed on the other side
    if (!joined.join(crossings[k], beyond->second, crossings[k + 2])) return true;
  }
  if (periodic_axis) return false;
  std::vector<char> low(static_cast<size_t>(labels), 0), high(static_cast<size_t>(labels), 0);
  for (size_t k = 0; k + 1 < ends.size(); k += 2) {
    long long lap = 0;
    const long long root = joined.find(ends[k], lap);
    (ends[k + 1] == 0 ? low : high)[root] = 1;
  }
  for (long long r = 0; r < labels; ++r)
    if (low[r] && high[r]) return true;
  return false;
}

float float_of_bits(std::uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
std::uint32_t bits_of_float(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

}  // namespace

VoxelBox voxel_box(const double* lo, const double* hi, int dimension, double voxel_size,
                   const std::array<long long, 3>& cell_voxels) {
  VoxelBox box;
  for (int d = 0; d < 3; ++d) {
    if (d >= dimension) {
      box.lo[d] = 0, box.hi[d] = cell_voxels[d];
      continue;
    }
    // Voxel i is the box's when its centre (i + 1/2) voxels is in [lo, hi), as a lattice point is.
    auto first_centre_from = [&](double x) {
      if (x <= 0) return 0LL;
      if (x >= cell_voxels[d] * voxel_size) return cell_voxels[d];
      return std::clamp(static_cast<long long>(std::ceil(x / voxel_size - 0.5)), 0LL, cell_voxels[d]);
    };
    box.lo[d] = first_centre_from(lo[d]);
    box.hi[d] = std::max(box.lo[d], first_centre_from(hi[d]));
  }
  return box;
}

long long ImagePiece::index_of_cell_voxel(const std::array<long long, 3>& c) const {
  long long index = 0;
  for (int d = 2; d >= 0; --d) {
    long long i = c[d] - first[d];
    if (wraps[d]) i = wrapped(i, cell[d]);
    index = index * voxels.shape[d] + i;
  }
  return index;
}

ImageWindow piece_window(const ImageLayout& layout, const VoxelBox& box, long long halo, ImagePiece& piece) {
  std::array<long long, 3> lo{}, hi{};
  piece_layers(layout, box, halo, piece, lo, hi);
  return window_of_layers(piece, lo, hi, layout.file_shape, layout.mirror_axis);
}

ImagePiece read_image_piece(const ImageSource& source, const ImageLayout& layout, const VoxelBox& box,
                            long long halo, const ImageSizeCheck& check) {
  ImagePiece piece;
  const ImageWindow window = piece_window(layout, box, halo, piece);
  piece.voxels = read_image_window(source, window, check);
  return piece;
}

ImagePiece cut_image_piece(const VoxelImage& cell_image, const ImageLayout& layout, const VoxelBox& box,
                           long long halo) {
  ImagePiece piece;
  std::array<long long, 3> lo{}, hi{};
  piece_layers(layout, box, halo, piece, lo, hi);
  piece.voxels = take_window(cell_image, window_of_layers(piece, lo, hi, cell_image.shape, -1));
  return piece;
}

long long walls_halo(double shell, double voxel_size) {
  const long long depth = static_cast<long long>(std::ceil(shell / voxel_size)) + 1;
  return kReach + depth + kReach + kSiteToSurface + kSurfaceDependence;
}

double piece_trusted_distance(long long halo, double voxel_size) {
  return static_cast<double>(halo - kSurfaceDependence - kSiteToSurface - 1) * voxel_size;
}

std::vector<float> piece_surface_distance(const ImagePiece& piece, const std::vector<int>& solid_values,
                                          double voxel_size) {
  const VoxelFrame frame{piece.first, piece.cell, piece.periodic};
  return surface_distance(piece.voxels, solid_values, voxel_size, piece.wraps, &frame);
}

bool pieces_percolate(const ImagePiece& piece, const std::vector<char>& open, int axis,
                      const std::array<bool, 3>& periodic, const Communicator& comm) {
  if (axis < 0 || axis >= piece.dimension) throw std::invalid_argument("pieces_percolate: no such axis");
  const BoxInPiece b = box_in_piece(piece);
  const BoxLabels local = label_box(piece, b, open);
  const long long offset = comm.sum_before(local.labels);
  const long long labels = comm.sum(static_cast<long long>(local.labels));
  std::vector<long long> faces, crossings, ends;
  auto cell_index = [&](const std::array<long long, 3>& c) {
    return c[0] + piece.cell[0] * (c[1] + piece.cell[1] * c[2]);
  };
  for (long long n = 0; n < b.total; ++n) {
    const int label = local.label[n];
    if (label < 0) continue;
    const long long global = offset + label;
    const std::array<long long, 3> c{{piece.box.lo[0] + n % b.count[0], piece.box.lo[1] + n / b.count[0] % b.count[1],
                                      piece.box.lo[2] + n / (b.count[0] * b.count[1])}};
    if (c[axis] == 0) ends.insert(ends.end(), {global, 0});
    if (c[axis] == piece.cell[axis] - 1) ends.insert(ends.end(), {global, 1});
    bool on_face = false;
    for (int d = 0; d < piece.dimension; ++d)
      for (int step : {-1, 1}) {
        std::array<long long, 3> beyond = c;
        beyond[d] += step;
        if (beyond[d] >= piece.box.lo[d] && beyond[d] < piece.box.hi[d]) continue;
        on_face = true;
        long long laps = 0;
        if (beyond[d] < 0 || beyond[d] >= piece.cell[d]) {
          if (!periodic[d]) continue;
          beyond[d] = wrapped(beyond[d], piece.cell[d]);
          if (d == axis) laps = step;
        }
        crossings.insert(crossings.end(), {global, cell_index(beyond), laps});
      }
    if (on_face) faces.insert(faces.end(), {cell_index(c), global});
  }
  const auto all_faces = comm.gather(faces), all_crossings = comm.gather(crossings), all_ends = comm.gather(ends);
  bool percolates = false;
  if (comm.rank() == 0)
    percolates = joined_labels_percolate(labels, all_faces, all_crossings, all_ends, periodic[axis]);
  return comm.broadcast(percolates);
}

double pieces_widest_path_width(const ImagePiece& piece, const std::vector<float>& distance, int axis,
                                const std::array<bool, 3>& periodic, double trusted, const Communicator& comm) {
  const BoxInPiece b = box_in_piece(piece);
  const float ceiling = static_cast<float>(trusted);
  std::vector<float> clamped(distance.size());
  for (size_t n = 0; n < distance.size(); ++n) clamped[n] = std::min(distance[n], ceiling);
  // The box's smallest and largest positive distances, over all processes.
  double lowest = INFINITY, highest = 0;
  for (long long n = 0; n < b.total; ++n) {
    const std::array<long long, 3> c{{piece.box.lo[0] + n % b.count[0], piece.box.lo[1] + n / b.count[0] % b.count[1],
                                      piece.box.lo[2] + n / (b.count[0] * b.count[1])}};
    const float d = clamped[static_cast<size_t>(piece.index_of_cell_voxel(c))];
    if (d > 0) lowest = std::min(lowest, static_cast<double>(d)), highest = std::max(highest, static_cast<double>(d));
  }
  lowest = comm.min(lowest);
  highest = comm.max(highest);
  std::vector<char> open(clamped.size());
  auto percolates_at = [&](float t) {
    for (size_t n = 0; n < open.size(); ++n) open[n] = clamped[n] >= t;
    return pieces_percolate(piece, open, axis, periodic, comm);
  };
  if (!std::isfinite(lowest) || !percolates_at(static_cast<float>(lowest))) return 0.0;
  if (percolates_at(static_cast<float>(highest))) return 2 * highest;
  // Percolation holds up to one distance that occurs and fails beyond it:
  // that distance is the largest float at which it holds, found by
  // bisection on the floats' bits (ordered as the positive floats are).
  std::uint32_t holds = bits_of_float(static_cast<float>(lowest)), fails = bits_of_float(static_cast<float>(highest));
  while (fails - holds > 1) {
    const std::uint32_t middle = holds + (fails - holds) / 2;
    (percolates_at(float_of_bits(middle)) ? holds : fails) = middle;
  }
  return 2 * static_cast<double>(float_of_bits(holds));
}

}  // namespace poresph
