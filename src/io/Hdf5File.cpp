#include "io/Hdf5File.hpp"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include "io/PathCheck.hpp"
#include "io/Summary.hpp"
#include "parallel/Communicator.hpp"

namespace poresph {
namespace {

template <class T>
hid_t memory_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, int>) return H5T_NATIVE_INT;
  else if constexpr (std::is_same_v<T, long long>) return H5T_NATIVE_LLONG;
  else if constexpr (std::is_same_v<T, char>) return H5T_NATIVE_CHAR;
  else static_assert(sizeof(T) == 0, "unsupported HDF5 element type");
}

// Closes an HDF5 handle at scope exit.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

// This process's part of a collective transfer; a process with nothing to
// move still takes part, with empty selections.
void select(hid_t file_space, hid_t memory_space, const hsize_t* start, const hsize_t* count, int n) {
  bool empty = false;
  for (int d = 0; d < n; ++d) empty = empty || count[d] == 0;
  if (empty) {
    H5Sselect_none(file_space);
    H5Sselect_none(memory_space);
  } else {
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  }
}

}  // namespace

Hdf5File::Hdf5File(const std::string& path, Mode mode, MPI_Comm comm) : path_(path), comm_(comm) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported as exceptions
  const Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  H5Pset_fapl_mpio(access.id, comm, MPI_INFO_NULL);
  file_ = mode == Mode::Create ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id)
                               : H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.id);
  if (file_ < 0) fail(mode == Mode::Create ? "cannot create the file" : "cannot open the file");
  transfer_ = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(transfer_, H5FD_MPIO_COLLECTIVE);
}

namespace {
bool left_broken = false;
}  // namespace

bool hdf5_left_broken() { return left_broken; }

Hdf5File::~Hdf5File() {
  if (transfer_ >= 0) H5Pclose(transfer_);
  // A close that fails (its last write on a full disk) leaves the file half
  // closed in HDF5 1.10.8, which crashes when it tries again at MPI_Finalize.
  if (file_ >= 0 && H5Fclose(file_) < 0) left_broken = true;
}

void Hdf5File::close() {
  if (transfer_ >= 0) H5Pclose(transfer_);
  transfer_ = -1;
  const hid_t file = file_;
  file_ = -1;
  if (file >= 0 && H5Fclose(file) < 0) {
    left_broken = true;
    fail("cannot complete the file (writing its last data and metadata)");
  }
}

namespace {

// The innermost entries of HDF5's error stack: the reason ("No space left on
// device" from the MPI-IO layer) that the failed API call alone does not give.
std::string hdf5_reason() {
  std::vector<std::string> reasons;
  const H5E_walk2_t collect = [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
    auto& found = *static_cast<std::vector<std::string>*>(data);
    if (error->desc && *error->desc) found.push_back(error->desc);
    return found.size() >= 2;  // the two deepest say what happened; the rest is the call chain
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect, &reasons);
  H5Eclear2(H5E_DEFAULT);
  std::string text;
  for (const auto& r : reasons) text += (text.empty() ? "" : "; ") + r;
  return text;
}

// What the file system holding `path` has left: HDF5's MPI-IO driver
// reports a short write without the reason, and errno is gone by then; a
// full disk is the usual one, and this says whether it is.
std::string free_space(const std::string& path) {
  struct statvfs fs {};
  const std::string dir = std::filesystem::absolute(path).parent_path().string();
  if (statvfs(dir.c_str(), &fs) != 0) return "";
  const double available = static_cast<double>(fs.f_bavail) * fs.f_frsize;
  const double total = static_cast<double>(fs.f_blocks) * fs.f_frsize;
  auto size = [](double bytes) {
    const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB"};
    int u = 0;
    while (bytes >= 1000 && u < 5) bytes /= 1000, ++u;
    char text[32];
    std::snprintf(text, sizeof text, "%.3g %s", bytes, units[u]);
    return std::string(text);
  };
  return (available < 1048576 ? "the disk is full: " : "") + size(available) + " of " + size(total) +
         " free on its file system";
}

}  // namespace

void Hdf5File::fail(const std::string& what) const {
  std::string reason = hdf5_reason();
  if (what.rfind("cannot write", 0) == 0 || what.rfind("cannot create", 0) == 0 ||
      what.rfind("cannot complete", 0) == 0) {
    const std::string space = free_space(path_);
    if (!space.empty()) reason += (reason.empty() ? "" : "; ") + space;
  }
  throw std::runtime_error(path_ + ": " + what + (reason.empty() ? "" : " (" + reason + ")"));
}

template <class T>
long long Hdf5File::write_rows(const std::string& name, const T* data, long long local_rows, int columns) {
  const Communicator comm(comm_);
  const long long offset = comm.sum_before(local_rows), total = comm.sum(local_rows);
  const int rank_of_data = columns > 0 ? 2 : 1;
  const hsize_t global[2] = {static_cast<hsize_t>(total), static_cast<hsize_t>(columns)};
  const hsize_t start[2] = {static_cast<hsize_t>(offset), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(local_rows), static_cast<hsize_t>(columns)};
  const Handle file_space{H5Screate_simple(rank_of_data, global, nullptr), H5Sclose};
  // A name such as "run/boxes" creates its group.
  const Handle link{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(link.id, 1);
  const Handle dataset{H5Dcreate2(file_, name.c_str(), memory_type<T>(), file_space.id, link.id, H5P_DEFAULT,
                                  H5P_DEFAULT),
                       H5Dclose};
  if (dataset.id < 0) fail("cannot create dataset " + name);
  if (total == 0) return offset;  // an empty array has no storage to write to (HDF5 refuses the write)
  const Handle memory_space{H5Screate_simple(rank_of_data, count, nullptr), H5Sclose};
  select(file_space.id, memory_space.id, start, count, rank_of_data);
  if (H5Dwrite(dataset.id, memory_type<T>(), memory_space.id, file_space.id, transfer_, data) < 0)
    fail("cannot write dataset " + name);
  return offset;
}

template <class T>
std::vector<T> Hdf5File::read_rows(const std::string& name, long long first, long long count_rows) {
  const Handle dataset{H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0) fail("no dataset " + name);
  const Handle file_space{H5Dget_space(dataset.id), H5Sclose};
  hsize_t dims[2] = {0, 1};
  const int rank_of_data = H5Sget_simple_extent_ndims(file_space.id);
  if (rank_of_data < 1 || rank_of_data > 2) fail(name + " is not a particle array");
  H5Sget_simple_extent_dims(file_space.id, dims, nullptr);
  const hsize_t columns = rank_of_data == 2 ? dims[1] : 1;
  if (first < 0 || count_rows < 0 || static_cast<hsize_t>(first + count_rows) > dims[0])
    fail("rows " + std::to_string(first) + ".." + std::to_string(first + count_rows) + " of " + name +
         " are out of range");
  std::vector<T> values(static_cast<size_t>(count_rows) * columns);
  if (dims[0] == 0) return values;  // every process sees the same empty array: no collective read to join
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(count_rows), columns};
  const Handle memory_space{H5Screate_simple(rank_of_data, count, nullptr), H5Sclose};
  select(file_space.id, memory_space.id, start, count, rank_of_data);
  if (H5Dread(dataset.id, memory_type<T>(), memory_space.id, file_space.id, transfer_, values.data()) < 0)
    fail("cannot read dataset " + name);
  return values;
}

template long long Hdf5File::write_rows<double>(const std::string&, const double*, long long, int);
template long long Hdf5File::write_rows<int>(const std::string&, const int*, long long, int);
template long long Hdf5File::write_rows<long long>(const std::string&, const long long*, long long, int);
template long long Hdf5File::write_rows<char>(const std::string&, const char*, long long, int);
template std::vector<char> Hdf5File::read_rows<char>(const std::string&, long long, long long);
template std::vector<double> Hdf5File::read_rows<double>(const std::string&, long long, long long);
template std::vector<int> Hdf5File::read_rows<int>(const std::string&, long long, long long);
template std::vector<long long> Hdf5File::read_rows<long long>(const std::string&, long long, long long);

void Hdf5File::write_block(const std::string& name, const std::vector<long long>& global,
                           const std::vector<long long>& offset, const std::vector<long long>& count,
                           const double* data) {
  const int n = static_cast<int>(global.size());
  std::vector<hsize_t> g(global.begin(), global.end()), o(offset.begin(), offset.end()),
      c(count.begin(), count.end());
  const Handle file_space{H5Screate_simple(n, g.data(), nullptr), H5Sclose};
  const Handle dataset{H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, file_space.id, H5P_DEFAULT, H5P_DEFAULT,
                                  H5P_DEFAULT),
                       H5Dclose};
  if (dataset.id < 0) fail("cannot create dataset " + name);
  const Handle memory_space{H5Screate_simple(n, c.data(), nullptr), H5Sclose};
  select(file_space.id, memory_space.id, o.data(), c.data(), n);
  if (H5Dwrite(dataset.id, H5T_NATIVE_DOUBLE, memory_space.id, file_space.id, transfer_, data) < 0)
    fail("cannot write dataset " + name);
}

bool Hdf5File::has(const std::string& name) const { return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0; }

std::vector<long long> Hdf5File::shape(const std::string& name) const {
  const Handle dataset{H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0) fail("no dataset " + name);
  const Handle space{H5Dget_space(dataset.id), H5Sclose};
  const int n = H5Sget_simple_extent_ndims(space.id);
  std::vector<hsize_t> dims(n > 0 ? n : 0);
  H5Sget_simple_extent_dims(space.id, dims.data(), nullptr);
  return {dims.begin(), dims.end()};
}

void Hdf5File::set_attribute(const std::string& name, double value) {
  set_attribute(name, std::vector<double>{value});
}

void Hdf5File::set_attribute(const std::string& name, const std::vector<double>& values) {
  const hsize_t n = values.size();
  const Handle space{n > 0 ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_NULL), H5Sclose};
  const Handle attribute{H5Acreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space.id, H5P_DEFAULT, H5P_DEFAULT),
                         H5Aclose};
  if (attribute.id < 0 || (n > 0 && H5Awrite(attribute.id, H5T_NATIVE_DOUBLE, values.data()) < 0))
    fail("cannot write attribute " + name);
}

void Hdf5File::set_attribute(const std::string& name, long long value) {
  const Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  const Handle attribute{H5Acreate2(file_, name.c_str(), H5T_NATIVE_LLONG, space.id, H5P_DEFAULT, H5P_DEFAULT),
                         H5Aclose};
  if (attribute.id < 0 || H5Awrite(attribute.id, H5T_NATIVE_LLONG, &value) < 0)
    fail("cannot write attribute " + name);
}

void Hdf5File::set_attribute(const std::string& name, const std::string& value) {
  // H5T_C_S1 is null-terminated: the size counts the terminator, or readers
  // that honour it (h5py) lose the last character.
  const Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.size() + 1);
  const Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  const Handle attribute{H5Acreate2(file_, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  if (attribute.id < 0 || H5Awrite(attribute.id, type.id, value.c_str()) < 0) fail("cannot write attribute " + name);
}

void Hdf5File::set_dataset_attribute(const std::string& dataset_name, const std::string& name, long long value) {
  const Handle dataset{H5Dopen2(file_, dataset_name.c_str(), H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0) fail("no dataset " + dataset_name);
  const Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  const Handle attribute{H5Acreate2(dataset.id, name.c_str(), H5T_NATIVE_LLONG, space.id, H5P_DEFAULT, H5P_DEFAULT),
                         H5Aclose};
  if (attribute.id < 0 || H5Awrite(attribute.id, H5T_NATIVE_LLONG, &value) < 0)
    fail("cannot write attribute " + name + " of " + dataset_name);
}

long long Hdf5File::dataset_integer_attribute(const std::string& dataset_name, const std::string& name) const {
  const Handle dataset{H5Dopen2(file_, dataset_name.c_str(), H5P_DEFAULT), H5Dclose};
  if (dataset.id < 0) fail("no dataset " + dataset_name);
  const Handle attribute{H5Aopen(dataset.id, name.c_str(), H5P_DEFAULT), H5Aclose};
  long long value = 0;
  if (attribute.id < 0 || H5Aread(attribute.id, H5T_NATIVE_LLONG, &value) < 0)
    fail("no attribute " + name + " of " + dataset_name);
  return value;
}

hid_t Hdf5File::open_attribute(const std::string& name) const {
  const hid_t attribute = H5Aopen(file_, name.c_str(), H5P_DEFAULT);
  if (attribute < 0) fail("no attribute " + name);
  return attribute;
}

std::vector<double> Hdf5File::double_array_attribute(const std::string& name) const {
  const Handle attribute{open_attribute(name), H5Aclose};
  const Handle space{H5Aget_space(attribute.id), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.id);
  std::vector<double> values(n > 0 ? n : 0);
  if (n > 0 && H5Aread(attribute.id, H5T_NATIVE_DOUBLE, values.data()) < 0) fail("cannot read attribute " + name);
  return values;
}

double Hdf5File::double_attribute(const std::string& name) const {
  const auto values = double_array_attribute(name);
  if (values.size() != 1) fail("attribute " + name + " is not a scalar");
  return values[0];
}

long long Hdf5File::integer_attribute(const std::string& name) const {
  const Handle attribute{open_attribute(name), H5Aclose};
  long long value = 0;
  if (H5Aread(attribute.id, H5T_NATIVE_LLONG, &value) < 0) fail("cannot read attribute " + name);
  return value;
}

std::string Hdf5File::string_attribute(const std::string& name) const {
  const Handle attribute{open_attribute(name), H5Aclose};
  const Handle type{H5Aget_type(attribute.id), H5Tclose};
  std::string value(H5Tget_size(type.id), '\0');
  if (H5Aread(attribute.id, type.id, value.data()) < 0) fail("cannot read attribute " + name);
  while (!value.empty() && value.back() == '\0') value.pop_back();
  return value;
}

std::string hdf5_file_problem(const std::string& path) {
  if (const std::string problem = regular_file_problem(path, "a file"); !problem.empty()) return problem;
  std::ifstream in(path, std::ios::binary);
  char signature[8] = {};
  if (!in.read(signature, sizeof signature)) return in.is_open() ? "it is too short to be an HDF5 file" : std::strerror(errno);
  // The HDF5 superblock signature; PoreSPH writes no user block before it.
  static const char hdf5[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  if (std::memcmp(signature, hdf5, sizeof hdf5) != 0) return "it is not an HDF5 file";
  return "";
}

void write_hdf5_atomically(const std::string& path, MPI_Comm comm, const std::function<void(Hdf5File&)>& fill) {
  const std::string temporary = path + ".tmp";
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  try {
    Hdf5File file(temporary, Hdf5File::Mode::Create, comm);
    fill(file);
    file.close();  // a full disk often shows only here, when the last blocks are flushed
  } catch (...) {  // closed by now; a partial file must not stay behind (on a full disk, least of all)
    if (rank == 0) std::remove(temporary.c_str());
    throw;
  }
  MPI_Barrier(comm);
  // On the disk before it takes the final name (a power loss then leaves the
  // previous file or this one, never an empty one under the name), and the
  // rename after it.
  int failed = 0;
  std::string step;
  if (rank == 0) {
    const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) failed = errno, step = "cannot sync " + temporary + " to the disk";
    if (fd >= 0) ::close(fd);
    if (!failed && std::rename(temporary.c_str(), path.c_str()) != 0)
      failed = errno, step = "cannot rename " + temporary + " to " + path;
    if (failed) std::remove(temporary.c_str());
    else sync_directory_of(path);
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, comm);
  if (failed) {
    int length = static_cast<int>(step.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, comm);
    step.resize(static_cast<size_t>(length));
    MPI_Bcast(step.data(), length, MPI_CHAR, 0, comm);
    throw std::runtime_error(step + ": " + std::strerror(failed));
  }
}

}  // namespace poresph
