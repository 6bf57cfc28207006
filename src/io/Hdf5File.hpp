#pragma once
// A parallel HDF5 file that every process opens together (MPI-IO). Particle
// arrays are written as row slabs: each process writes its rows at the offset
// given by the processes before it, collectively, so the file holds one
// contiguous array per field whatever the number of processes. Gridded
// fields are written as blocks of a global array. Errors throw with the file
// and dataset named; no HDF5 error stack is printed.
#include <hdf5.h>
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

namespace poresph {

class Hdf5File {
 public:
  enum class Mode { Create, Read };
  // Create truncates; every process of comm must call it.
  Hdf5File(const std::string& path, Mode mode, MPI_Comm comm);
  ~Hdf5File();
  // Closes collectively and throws if the file could not be completed; the
  // destructor closes too, but cannot report a failure.
  void close();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  // Writes rows [offset, offset + local_rows) of a global array of
  // sum(local_rows) x columns (columns 0: one-dimensional). Returns the offset.
  template <class T>
  long long write_rows(const std::string& name, const T* data, long long local_rows, int columns);
  // Rows [first, first + count) of a dataset written by write_rows.
  template <class T>
  std::vector<T> read_rows(const std::string& name, long long first, long long count);

  // A block of a global array of shape `global` (slowest index first): this
  // process's part starts at `offset` and has shape `count`.
  void write_block(const std::string& name, const std::vector<long long>& global,
                   const std::vector<long long>& offset, const std::vector<long long>& count, const double* data);

  bool has(const std::string& name) const;
  std::vector<long long> shape(const std::string& name) const;

  // Scalar and vector attributes of the root group ("/"), written by every process with the same value.
  // Attributes are kept in the object header, which holds 64 kB: anything that
  // may grow (a parameter list, a list of frames) belongs in a dataset.
  void set_attribute(const std::string& name, double value);
  void set_attribute(const std::string& name, long long value);
  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, const std::vector<double>& values);
  // An integer attribute of a dataset (its checksum, say).
  void set_dataset_attribute(const std::string& dataset, const std::string& name, long long value);
  long long dataset_integer_attribute(const std::string& dataset, const std::string& name) const;
  double double_attribute(const std::string& name) const;
  long long integer_attribute(const std::string& name) const;
  std::string string_attribute(const std::string& name) const;
  std::vector<double> double_array_attribute(const std::string& name) const;

  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& what) const;
  hid_t open_attribute(const std::string& name) const;

  std::string path_;
  MPI_Comm comm_;
  hid_t file_ = -1;
  hid_t transfer_ = -1;  // collective transfers
};

// Whether a file failed to close (on a full disk): HDF5 1.10.8 then holds a
// half-closed file that crashes the process when it tries to close it again
// at MPI_Finalize, so the program ends without finalizing (app/main.cpp).
bool hdf5_left_broken();

// Why `path` cannot be read as an HDF5 file, or "" if it can be tried: it is
// missing, a directory or not a regular file, unreadable, or does not start
// with the HDF5 signature. Asked before opening: MPI-IO prints its own
// complaints, dozens of lines on several processes, about a directory.
std::string hdf5_file_problem(const std::string& path);

// Every process of comm writes through fill() into PATH.tmp; once the file
// is closed on all of them, rank 0 renames it to PATH. A crash in between
// leaves the previous PATH (or none), never a truncated one.
void write_hdf5_atomically(const std::string& path, MPI_Comm comm, const std::function<void(Hdf5File&)>& fill);

}  // namespace poresph
