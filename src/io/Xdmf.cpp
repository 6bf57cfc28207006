#include "io/Xdmf.hpp"

#include <cstdio>
#include <sstream>

namespace poresph {
namespace {

std::string joined(const std::vector<long long>& values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) text += (i ? " " : "") + std::to_string(values[i]);
  return text;
}

std::string joined(const std::vector<double>& values) {
  std::string text;
  char buffer[32];
  for (size_t i = 0; i < values.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%s%.17g", i ? " " : "", values[i]);
    text += buffer;
  }
  return text;
}

void data_item(std::ostringstream& out, const std::string& file, const std::string& dataset,
               const std::vector<long long>& dims, bool integer, int bytes, const char* indent) {
  out << indent << "<DataItem Format=\"HDF\" NumberType=\"" << (integer ? "Int" : "Float") << "\" Precision=\""
      << bytes << "\" Dimensions=\"" << joined(dims) << "\">" << file << ":" << dataset << "</DataItem>\n";
}

}  // namespace

std::string xdmf_time_series(const std::string& name, const std::vector<XdmfFrame>& frames) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n"
      << "    <Grid Name=\"" << name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  char time[32];
  for (const auto& frame : frames) {
    std::snprintf(time, sizeof time, "%.17g", frame.time);
    out << "      <Grid Name=\"" << name << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << time << "\"/>\n";
    const auto& mesh = frame.mesh;
    if (mesh.regular_grid) {
      const bool three = mesh.points.size() == 3;
      out << "        <Topology TopologyType=\"" << (three ? "3DCoRectMesh" : "2DCoRectMesh") << "\" Dimensions=\""
          << joined(mesh.points) << "\"/>\n"
          << "        <Geometry GeometryType=\"" << (three ? "ORIGIN_DXDYDZ" : "ORIGIN_DXDY") << "\">\n"
          << "          <DataItem Format=\"XML\" Dimensions=\"" << mesh.origin.size() << "\">" << joined(mesh.origin)
          << "</DataItem>\n"
          << "          <DataItem Format=\"XML\" Dimensions=\"" << mesh.spacing.size() << "\">"
          << joined(mesh.spacing) << "</DataItem>\n"
          << "        </Geometry>\n";
    } else {
      out << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << mesh.count << "\"/>\n"
          << "        <Geometry GeometryType=\"XYZ\">\n";
      data_item(out, frame.file, mesh.positions, {mesh.count, 3}, false, 8, "          ");
      out << "        </Geometry>\n";
    }
    for (const auto& a : frame.attributes) {
      out << "        <Attribute Name=\"" << a.name << "\" AttributeType=\"" << (a.vector ? "Vector" : "Scalar")
          << "\" Center=\"Node\">\n";
      data_item(out, frame.file, a.dataset, a.dims, a.integer, a.bytes, "          ");
      out << "        </Attribute>\n";
    }
    out << "      </Grid>\n";
  }
  out << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  return out.str();
}

}  // namespace poresph
