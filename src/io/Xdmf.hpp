#pragma once
// XDMF (version 2) descriptions of the HDF5 field files, so that ParaView
// opens a whole run as a time series: particles as points with attributes,
// the gridded view as an image. The text is rebuilt from the frame list each
// time a frame is added and written atomically, so an interrupted run still
// leaves a valid description of every complete file.
#include <string>
#include <vector>

namespace poresph {

// One array of an HDF5 file seen as an attribute of the mesh.
struct XdmfAttribute {
  std::string name;
  std::string dataset;         // path in the HDF5 file
  std::vector<long long> dims;  // last dimension 3 for a vector
  bool vector = false;
  bool integer = false;        // 4- or 8-byte integers instead of doubles
  int bytes = 8;
};

// The mesh of one frame: `count` points at `positions` (count x 3), or a
// regular grid of `points` per direction (slowest first: z y x) starting at
// `origin` with `spacing` (same order).
struct XdmfMesh {
  bool regular_grid = false;
  long long count = 0;
  std::string positions;
  std::vector<long long> points;
  std::vector<double> origin, spacing;
};

struct XdmfFrame {
  double time = 0;
  std::string file;  // relative to the .xmf file
  XdmfMesh mesh;
  std::vector<XdmfAttribute> attributes;
};

// The whole time series as XDMF text.
std::string xdmf_time_series(const std::string& name, const std::vector<XdmfFrame>& frames);

}  // namespace poresph
