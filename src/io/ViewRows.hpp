#pragma once
// Owned rows of particle Views to and from contiguous host arrays: what the
// field files and checkpoints write and read.
#include <Kokkos_Core.hpp>

#include <type_traits>
#include <vector>

namespace poresph {

// Owned rows of a View as a contiguous host array (View layouts may pad).
template <class View>
auto owned_rows(const View& view, int owned) {
  using Value = typename View::non_const_value_type;
  const int columns = View::rank == 2 ? static_cast<int>(view.extent(1)) : 1;
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<Value> rows(static_cast<size_t>(owned) * columns);
  for (int i = 0; i < owned; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 2) rows[static_cast<size_t>(i) * columns + c] = host(i, c);
      else rows[i] = host(i);
    }
  return rows;
}

// f(data): the owned rows of a View as a contiguous host array, read in
// place where the View is on the host and its rows are contiguous (a
// checkpoint of a large scene then copies no field), else from owned_rows.
template <class View, class F>
void with_owned_rows(const View& view, int owned, F&& f) {
  using Layout = typename View::array_layout;
  constexpr bool host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename View::memory_space>::accessible;
  constexpr bool rows_contiguous = View::rank == 1 || std::is_same_v<Layout, Kokkos::LayoutRight>;
  if constexpr (host && rows_contiguous) {
    if (view.span_is_contiguous()) return f(view.data());
  }
  const auto rows = owned_rows(view, owned);
  f(rows.data());
}

// Writes rows back into the first rows of a View.
template <class View, class Value>
void load_rows(const View& view, const std::vector<Value>& rows) {
  auto host = Kokkos::create_mirror_view(view);
  const int columns = View::rank == 2 ? static_cast<int>(view.extent(1)) : 1;
  const size_t count = rows.size() / columns;
  Kokkos::deep_copy(host, view);
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < columns; ++c) {
      if constexpr (View::rank == 2) host(i, c) = rows[i * columns + c];
      else host(i) = rows[i];
    }
  Kokkos::deep_copy(view, host);
}

}  // namespace poresph
