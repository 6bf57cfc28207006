#pragma once
// Ghosts and migration across processes (MPI), the paper's staged exchange
// (section 5) generalised to boxes that do not form a process grid.
//
// Stage d (x, then y, then z) sends each particle a process holds (owned, or
// a ghost from an earlier stage) to every process q whose stage-d halo
// region holds the particle, shifted by -L_d, 0 or +L_d along d:
//   within the support width of q's box along d but outside it,
//   inside q's box along later directions,
//   within the width of q's box along earlier directions.
// These regions tile each process's halo, and a ghost is sent only by its
// canonical sender: the owner of the point that has the particle's own
// coordinates along d and later directions and q's nearest coordinates along
// earlier ones. So each ghost arrives exactly once; corners travel through
// the second stage; a face may have any number of neighbours; a process
// spanning a periodic direction sends to itself; boxes thinner than the
// width receive from beyond their neighbours.
//
// build() makes the ghosts and records the routes; update() sends the
// changing fields along the same routes; migrate() hands owned particles
// that left the box to their new owners.
#include <Kokkos_Core.hpp>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/Particles.hpp"
#include "parallel/Communicator.hpp"
#include "parallel/Decomposition.hpp"

namespace poresph {

template <int Dim, class ExecSpace>
class Halo {
 public:
  using MemorySpace = typename ExecSpace::memory_space;
  using ParticleSet = Particles<Dim, MemorySpace>;
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible,
                "the halo packs messages on the host");

  Halo() = default;
  Halo(const Communicator& comm, const Decomposition<Dim>& decomposition, double width)
      : comm_(comm), decomposition_(decomposition), width_(width) {
    for (int d = 0; d < Dim; ++d)
      if (decomposition_.periodic()[d] && decomposition_.cell()[d] < width_) {
        std::ostringstream msg;
        msg << "periodic cell side " << d << " (" << decomposition_.cell()[d]
            << ") is narrower than the kernel support 3h plus skin (" << width_ << ")";
        throw std::invalid_argument(msg.str());
      }
  }

  const Box<Dim>& box() const { return decomposition_.box(comm_.rank()); }
  const Decomposition<Dim>& decomposition() const { return decomposition_; }

  // Puts owned particles that left the cell through a periodic face back in;
  // the start-of-step position moves with them (a wrap in the middle of a
  // step must not be undone by the corrector).
  void wrap(const ParticleSet& P) const {
    const auto x = P.x, x_start = P.x_start;
    const bool with_start = !P.fixed_positions;
    for (int i = 0; i < P.owned; ++i)
      for (int d = 0; d < Dim; ++d) {
        if (!decomposition_.periodic()[d]) continue;
        const double wrapped = wrap_coordinate(x(i, d), 0.0, decomposition_.cell()[d]);
        if (with_start) x_start(i, d) += wrapped - x(i, d);
        x(i, d) = wrapped;
      }
  }

  // Sends owned particles outside this box to their owners (ghosts are
  // dropped). Returns how many left.
  int migrate(ParticleSet& P) {
    P.ghosts = 0;
    auto& leaving = leaving_;
    auto& staying = staying_;
    leaving.clear();
    staying.clear();
    for (int i = 0; i < P.owned; ++i) {
      double xi[Dim];
      for (int d = 0; d < Dim; ++d) xi[d] = P.x(i, d);
      const int q = decomposition_.owner(xi);
      if (q < 0) throw std::runtime_error("particle " + std::to_string(P.id(i)) + " is outside every sub-domain");
      if (q == comm_.rank()) staying.push_back(i);
      else leaving.push_back({i, q, {}});
    }
    keep_headroom(leaving);
    keep_headroom(staying);
    sort_by_destination(leaving);
    const Transfer& transfer = exchange(ParticleFields{P, Fields::Owned}, leaving);
    // Stable compaction: the particles that stay keep their order.
    for (size_t k = 0; k < staying.size(); ++k)
      if (staying[k] != static_cast<int>(k)) copy_particle(P, staying[k], static_cast<int>(k), Fields::Owned);
    P.owned = static_cast<int>(staying.size());
    P.reserve(P.owned + transfer.received());
    unpack(ParticleFields{P, Fields::Owned}, transfer, P.owned);
    P.owned += transfer.received();
    return static_cast<int>(leaving.size());
  }

  // Replaces all ghosts; owned particles must be inside this box.
  void build(ParticleSet& P) {
    P.ghosts = 0;
    const auto& me = box();
    for (int d = 0; d < Dim; ++d) {
      const int held = P.total();
      auto& items = stages_[d].items;  // reused: a rebuild allocates only when a stage grows
      items.clear();
      for (int i = 0; i < held; ++i) {
        double x[Dim];
        for (int e = 0; e < Dim; ++e) x[e] = P.x(i, e);
        if (i < P.owned && deep_inside(me, x)) continue;  // nobody else needs it
        for (int q = 0; q < decomposition_.ranks(); ++q)
          for (int s = -1; s <= 1; ++s) {
            if (s != 0 && !decomposition_.periodic()[d]) continue;
            double shifted[Dim];
            for (int e = 0; e < Dim; ++e) shifted[e] = x[e];
            shifted[d] += s * decomposition_.cell()[d];
            if (in_stage_region(decomposition_.box(q), shifted, d) && canonical_sender(q, x, d) == comm_.rank())
              items.push_back({i, q, static_cast<double>(s) * decomposition_.cell()[d]});
          }
      }
      keep_headroom(items);
      sort_by_destination(items);
      const Transfer& transfer = exchange(ParticleFields{P, Fields::Ghost}, items, d);
      P.reserve_ghosts(P.total() + transfer.received());
      unpack(ParticleFields{P, Fields::Ghost}, transfer, P.total());
      P.ghosts += transfer.received();
      stages_[d].recv_counts = transfer.recv_counts;
    }
    built_ = true;
  }

  // Gives back the room kept for later builds (a halo built once: fixed
  // particles); the routes stay, and an update's buffers take what it needs.
  void fit() {
    for (auto& stage : stages_) stage.items.shrink_to_fit();
    for (auto* buffer : {&transfer_.data, &send_buffer_}) buffer->clear(), buffer->shrink_to_fit();
    for (auto* buffer : {&leaving_, &sorted_items_}) buffer->clear(), buffer->shrink_to_fit();
    staying_.clear(), staying_.shrink_to_fit();
  }

  // Sends the fields that change between rebuilds along the recorded routes;
  // the counts are known from the build, so only the data travel.
  void update(ParticleSet& P) {
    if (!built_) return;
    update_carried(ParticleFields{P, Fields::Changing}, P.owned);
  }

  // The same for values that are no particle's field: a view with a value
  // (rank 1) or a row of values (rank 2) per slot, of at least the particles'
  // slots, sent from the owned slots [0, owned) to the ghost slots (the
  // steady solver's perturbations: physics/LatticeProducts.hpp). Periodic
  // images take the values as they are.
  template <class Values>
  void update_values(const Values& values, int owned) {
    if (!built_) return;
    update_carried(LooseValues<Values>{values}, owned);
  }

  static double wrap_coordinate(double x, double lo, double hi) {
    const double length = hi - lo;
    if (x >= hi) x -= length;
    else if (x < lo) {
      x += length;
      if (x >= hi) x = lo;
    }
    return x;
  }

 private:
  enum class Fields { Ghost, Changing, Owned };
  struct Item {
    int index;     // local particle
    int to;        // destination rank
    double shift;  // along the stage's direction
  };
  struct Stage {
    std::vector<Item> items;        // what this process sends, in destination order
    std::vector<int> recv_counts;   // what it receives from each rank
  };
  struct Transfer {
    std::vector<double> data;       // from the other processes, in rank order
    std::vector<int> recv_counts;   // from each rank, this one's own included
    int width = 0;
    // What this process sends itself (periodic images): not packed, but
    // copied slot to slot at the unpack, so that a process alone holds no
    // buffer at all. Its items, where they begin among the received, and
    // the stage's direction (the image shift's component).
    const Item* own = nullptr;
    int own_first = 0, direction = 0;
    int received() const {
      int n = 0;
      for (int c : recv_counts) n += c;
      return n;
    }
  };

  template <class F>
  static void visit(const ParticleSet& P, Fields fields, F&& f) {
    if (fields == Fields::Ghost) P.for_each_ghost_field(f);
    else if (fields == Fields::Changing) P.for_each_changing_field(f);
    else P.for_each_owned_field(f);
  }
  // What an exchange carries: a group of the particles' fields, whose first
  // is x (which takes the image shift) in every group but the changing
  // fields of fixed particles; or loose values, which take none.
  struct ParticleFields {
    const ParticleSet& P;
    Fields fields;
    template <class F>
    void operator()(F&& f) const {
      visit(P, fields, f);
    }
    bool shifted() const { return fields != Fields::Changing || !P.fixed_positions; }
  };
  template <class Values>
  struct LooseValues {
    Values values;
    template <class F>
    void operator()(F&& f) const {
      f(values);
    }
    bool shifted() const { return false; }
  };
  // The changing fields (or loose values) along the recorded routes, into the ghost slots from first_ghost on.
  template <class Carried>
  void update_carried(const Carried& carried, int first_ghost) {
    int slot = first_ghost;
    for (int d = 0; d < Dim; ++d) {
      const Transfer& transfer = exchange(carried, stages_[d].items, d, &stages_[d].recv_counts);
      unpack(carried, transfer, slot);
      slot += transfer.received();
    }
  }
  template <class View>
  static int components(const View& v) {
    return View::rank == 1 ? 1 : static_cast<int>(v.extent(1));
  }
  template <class View>
  static double get(const View& v, int i, int c) {
    if constexpr (View::rank == 1) return static_cast<double>(v(i));
    else return static_cast<double>(v(i, c));
  }
  template <class View>
  static void put(const View& v, int i, int c, double value) {
    using T = typename View::non_const_value_type;
    if constexpr (View::rank == 1) v(i) = static_cast<T>(value);
    else v(i, c) = static_cast<T>(value);
  }

  static void copy_particle(const ParticleSet& P, int from, int to, Fields fields) {
    visit(P, fields, [&](const auto& v) {
      for (int c = 0; c < components(v); ++c) put(v, to, c, get(v, from, c));
    });
  }

  // A buffer within a quarter of its capacity grows to twice its size, so
  // that the fluctuation of ghost counts from one rebuild to the next (rows
  // of particles crossing the halo's edge: 20 % and more) does not reallocate.
  template <class T>
  static void keep_headroom(std::vector<T>& buffer) {
    if (buffer.capacity() < buffer.size() + buffer.size() / 4 + 16) buffer.reserve(buffer.size() * 2 + 16);
  }

  // Orders items by destination rank, keeping their order within a rank: a
  // counting sort into a reused buffer (std::stable_sort would allocate).
  void sort_by_destination(std::vector<Item>& items) const {
    auto& start = sort_offsets_;
    start.assign(comm_.size() + 1, 0);
    for (const auto& it : items) ++start[it.to + 1];
    for (int q = 0; q < comm_.size(); ++q) start[q + 1] += start[q];
    sorted_items_.resize(items.size());
    keep_headroom(sorted_items_);
    for (const auto& it : items) sorted_items_[start[it.to]++] = it;
    std::copy(sorted_items_.begin(), sorted_items_.end(), items.begin());  // not swap: each keeps its capacity
  }

  // Packs the items (sorted by destination) and exchanges counts (unless
  // known) and data. The buffers are members, reused from call to call, so
  // that a step allocates nothing once they have grown to size.
  template <class Carried>
  const Transfer& exchange(const Carried& carried, const std::vector<Item>& items, int direction = 0,
                           const std::vector<int>* known_recv_counts = nullptr) const {
    Transfer& t = transfer_;
    t.width = 0;
    carried([&](const auto& v) { t.width += components(v); });
    const int ranks = comm_.size();
    auto& send_counts = send_counts_;
    send_counts.assign(ranks, 0);
    for (const auto& it : items) ++send_counts[it.to];
    // The items to this process itself (sorted by destination: one run) are
    // left out of the messages (unpack copies them).
    const int me = comm_.rank();
    size_t own_begin = 0;
    while (own_begin < items.size() && items[own_begin].to < me) ++own_begin;
    const size_t own_end = own_begin + send_counts[me];
    t.own = send_counts[me] > 0 ? items.data() + own_begin : nullptr;
    t.direction = direction;
    auto& send = send_buffer_;
    send.resize((items.size() - send_counts[me]) * t.width);
    keep_headroom(send);
    size_t packed = 0;
    for (size_t k = 0; k < items.size(); ++k) {
      if (k == own_begin && own_end > own_begin) k = own_end;
      if (k == items.size()) break;
      pack(carried, items[k], direction, &send[packed * t.width]);
      ++packed;
    }
    if (known_recv_counts) {
      t.recv_counts = *known_recv_counts;
    } else {
      t.recv_counts.assign(ranks, 0);
      const CommunicationTimer timer;
      MPI_Alltoall(send_counts.data(), 1, MPI_INT, t.recv_counts.data(), 1, MPI_INT, comm_.comm());
    }
    auto &sc = send_sizes_, &sd = send_offsets_, &rc = recv_sizes_, &rd = recv_offsets_;
    sc.resize(ranks), sd.resize(ranks), rc.resize(ranks), rd.resize(ranks);
    int s_off = 0, r_off = 0;
    t.own_first = 0;
    for (int q = 0; q < ranks; ++q) {
      if (q < me) t.own_first += t.recv_counts[q];
      const bool other = q != me;
      sc[q] = other ? send_counts[q] * t.width : 0, sd[q] = s_off, s_off += sc[q];
      rc[q] = other ? t.recv_counts[q] * t.width : 0, rd[q] = r_off, r_off += rc[q];
    }
    t.data.resize(r_off);
    keep_headroom(t.data);
    const CommunicationTimer timer;
    MPI_Alltoallv(send.data(), sc.data(), sd.data(), MPI_DOUBLE, t.data.data(), rc.data(), rd.data(), MPI_DOUBLE,
                  comm_.comm());
    return t;
  }

  // One item's fields into `out`, in the order of visit(), with the image
  // shift added to x (the first field of every group that has it: all but
  // the refresh of fixed particles, Particles::for_each_changing_field).
  template <class Carried>
  static void pack(const Carried& carried, const Item& item, int direction, double* out) {
    int offset = 0;
    carried([&](const auto& v) {
      for (int c = 0; c < components(v); ++c) out[offset + c] = get(v, item.index, c);
      offset += components(v);
    });
    if (carried.shifted()) out[direction] += item.shift;
  }

  // The received particles into slots [first_slot, first_slot + received):
  // from the messages, and this process's own items copied from their
  // slots (which lie below first_slot: a stage sends only what is held
  // before it) as a message would have brought them.
  template <class Carried>
  void unpack(const Carried& carried, const Transfer& t, int first_slot) const {
    const int n = t.received(), own = t.own ? t.recv_counts[comm_.rank()] : 0;
    std::vector<double>& row = own_row_;
    row.resize(t.width);
    for (int k = 0; k < n; ++k) {
      const bool from_self = k >= t.own_first && k < t.own_first + own;
      const double* in = row.data();
      if (from_self) pack(carried, t.own[k - t.own_first], t.direction, row.data());
      else in = &t.data[(k < t.own_first ? k : k - own) * t.width];
      int offset = 0;
      carried([&](const auto& v) {
        for (int c = 0; c < components(v); ++c) put(v, first_slot + k, c, in[offset + c]);
        offset += components(v);
      });
    }
  }

  bool deep_inside(const Box<Dim>& b, const double* x) const {
    for (int d = 0; d < Dim; ++d)
      if (x[d] < b.lo[d] + width_ || x[d] >= b.hi[d] - width_) return false;
    return true;
  }

  bool in_stage_region(const Box<Dim>& q, const double* x, int d) const {
    if (!(x[d] >= q.lo[d] - width_ && x[d] < q.hi[d] + width_)) return false;
    if (x[d] >= q.lo[d] && x[d] < q.hi[d]) return false;  // inside along d: not a stage-d ghost
    for (int e = 0; e < Dim; ++e) {
      if (e == d) continue;
      const double lo = e < d ? q.lo[e] - width_ : q.lo[e], hi = e < d ? q.hi[e] + width_ : q.hi[e];
      if (!(x[e] >= lo && x[e] < hi)) return false;
    }
    return true;
  }

  // The owner of the point with x's coordinates along d and later directions
  // and the nearest coordinates of q's box along earlier ones. Along earlier
  // directions x already carries its image shift and the stage region is
  // tested against q's box as it is, so the nearest point is taken in that
  // same frame: it lies in q's box, inside the cell, within the width of x.
  int canonical_sender(int q, const double* x, int d) const {
    const auto& b = decomposition_.box(q);
    double z[Dim];
    for (int e = 0; e < Dim; ++e)
      z[e] = e < d ? std::clamp(x[e], b.lo[e], std::nextafter(b.hi[e], b.lo[e])) : x[e];
    return decomposition_.owner(z);
  }

  Communicator comm_;
  Decomposition<Dim> decomposition_;
  double width_ = 0;
  std::array<Stage, Dim> stages_;
  bool built_ = false;
  // Reused buffers (see exchange).
  std::vector<Item> leaving_;
  std::vector<int> staying_;
  mutable Transfer transfer_;
  mutable std::vector<double> send_buffer_;
  mutable std::vector<int> send_counts_, send_sizes_, send_offsets_, recv_sizes_, recv_offsets_, sort_offsets_;
  mutable std::vector<Item> sorted_items_;
  mutable std::vector<double> own_row_;  // one particle copied to itself (unpack)
};

}  // namespace poresph
