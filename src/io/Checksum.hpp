#pragma once
// A checksum of an array's rows that does not depend on which process held
// which rows: the sum, modulo 2^64, of a hash of each row's bytes mixed with
// the row's global index. Each process sums its own rows and the sums add
// up, so a checkpoint written by 4 processes is checked when 2 read it. A
// zeroed or altered block changes the sum (but for a chance of 2^-64); a
// row moved to another index does too.
#include <cstddef>
#include <cstdint>

namespace poresph {

// The splitmix64 finaliser: spreads every input bit over the whole word.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Rows [first_row, first_row + rows) of a global array, `values_per_row` values of T each.
template <class T>
std::uint64_t row_checksum(const T* data, long long rows, long long values_per_row, long long first_row) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  const std::size_t row_bytes = sizeof(T) * static_cast<std::size_t>(values_per_row);
  std::uint64_t sum = 0;
  for (long long r = 0; r < rows; ++r) {
    std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a over the row's bytes
    for (std::size_t b = 0; b < row_bytes; ++b) h = (h ^ bytes[r * row_bytes + b]) * 0x100000001b3ULL;
    sum += mix64(h ^ mix64(static_cast<std::uint64_t>(first_row + r)));
  }
  return sum;
}

}  // namespace poresph
