#pragma once
// A CSV file a run appends rows to as it goes (permeability_history*.csv,
// profiles.csv), on the one process that writes it. A fresh run creates it
// with its header. A run that continues from the checkpoint in its own
// directory cuts it back to the header and the rows the checkpoint counts,
// so that rows a killed run wrote after its last checkpoint, or the
// end-of-run row of a run continued past its end, are not there twice.
// Every write is checked: a full disk stops the run with the reason, it does
// not leave a history with a silent hole.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/Summary.hpp"

namespace poresph {

class HistoryFile {
 public:
  void open(const std::string& path, const std::string& header, bool continuing, long long keep_rows) {
    path_ = path;
    if (continuing) {
      std::ifstream old(path);
      if (old) {
        // The header and the first keep_rows rows, written back whole before appending.
        std::string kept, line;
        for (long long n = -1; n < keep_rows && std::getline(old, line); ++n) kept += line + "\n";
        old.close();
        write_file_atomically(path, kept.empty() ? header : kept);
        file_.open(path, std::ios::out | std::ios::app);
        opened();
        return;
      }
    }
    file_.open(path, std::ios::out | std::ios::trunc);
    opened();
    file_ << header;
    check();
  }

  // The stream rows go to; null where this process does not write.
  std::ofstream* stream() { return file_.is_open() ? &file_ : nullptr; }
  std::ofstream& file() { return file_; }

  // After writing: throws with the reason if the stream failed.
  void check() {
    if (!file_.is_open()) return;
    file_.flush();
    if (!file_) throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  }

 private:
  void opened() {
    if (!file_.is_open()) throw std::runtime_error("cannot open " + path_ + ": " + std::strerror(errno));
  }

  std::string path_;
  std::ofstream file_;
};

}  // namespace poresph
