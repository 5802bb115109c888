#include "parallel_context_mpi.h"

#include "mpi_check.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>

namespace tessera::insitu {
namespace {

constexpr int kPixelTag = 0x7e55;
constexpr int kAuxTag = 0x7e56;  ///< image.denoise: the auxiliary sums, beside the pixels
static_assert(std::is_trivially_copyable_v<PixelSums>, "pixels travel as raw bytes");
static_assert(std::is_trivially_copyable_v<AuxSums>, "auxiliary sums travel as raw bytes");

using detail::check;

std::string box_text(const std::int64_t offset[3], const std::int64_t dims[3]) {
  std::string s = "[";
  for (int a = 0; a < 3; ++a)
    s += (a ? ", " : "") + std::to_string(offset[a]) + ".." + std::to_string(offset[a] + dims[a]);
  return s + ")";
}

MPI_Datatype element_type(DType t) {
  switch (t) {
    case DType::UInt8: return MPI_UINT8_T;
    case DType::Int16: return MPI_INT16_T;
    case DType::UInt16: return MPI_UINT16_T;
    case DType::Float32: return MPI_FLOAT;
    case DType::Float64: default: return MPI_DOUBLE;
  }
}

/// Owns committed derived datatypes until the end of a scope.
class TypeList {
 public:
  ~TypeList() {
    for (MPI_Datatype& t : m_types) MPI_Type_free(&t);
  }
  MPI_Datatype commit(MPI_Datatype t) {
    m_types.push_back(t);
    check(MPI_Type_commit(&m_types.back()), "MPI_Type_commit");
    return t;
  }

 private:
  std::vector<MPI_Datatype> m_types;
};

/// One element per vertex of a strided view, addressed relative to view.data: nested hvectors
/// over the view's byte strides, so MPI reads the simulation's array in place.
MPI_Datatype strided_view_type(const FieldView& v, TypeList& keep) {
  MPI_Datatype row, plane, box;
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[0]), 1, v.byte_strides[0],
                                element_type(v.dtype), &row), "MPI_Type_create_hvector");
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[1]), 1, v.byte_strides[1], row, &plane),
        "MPI_Type_create_hvector");
  check(MPI_Type_create_hvector(static_cast<int>(v.dims[2]), 1, v.byte_strides[2], plane, &box),
        "MPI_Type_create_hvector");
  MPI_Type_free(&row);
  MPI_Type_free(&plane);
  return keep.commit(box);
}

/// The sub-box [offset, offset + dims) of the C-order replica of global_dims vertices.
MPI_Datatype replica_box_type(DType dtype, const std::int64_t global[3], const std::int64_t offset[3],
                              const std::int64_t dims[3], TypeList& keep) {
  // MPI_ORDER_C lists the slowest axis first: k, j, i.
  const int sizes[3] = {static_cast<int>(global[2]), static_cast<int>(global[1]), static_cast<int>(global[0])};
  const int sub[3] = {static_cast<int>(dims[2]), static_cast<int>(dims[1]), static_cast<int>(dims[0])};
  const int start[3] = {static_cast<int>(offset[2]), static_cast<int>(offset[1]), static_cast<int>(offset[0])};
  MPI_Datatype t;
  check(MPI_Type_create_subarray(3, sizes, sub, start, MPI_ORDER_C, element_type(dtype), &t),
        "MPI_Type_create_subarray");
  return keep.commit(t);
}

/// Copies a strided view into its box of the C-order replica: one copy, no staging buffer.
template <std::size_t E>
void copy_box_typed(const FieldView& v, unsigned char* replica, const std::int64_t global[3],
                    const std::int64_t offset[3]) {
  const auto* src0 = static_cast<const unsigned char*>(v.data);
  const std::int64_t s0 = v.byte_strides[0];
  for (std::int64_t k = 0; k < v.dims[2]; ++k)
    for (std::int64_t j = 0; j < v.dims[1]; ++j) {
      const unsigned char* src = src0 + j * v.byte_strides[1] + k * v.byte_strides[2];
      unsigned char* dst = replica + E * (((offset[2] + k) * global[1] + offset[1] + j) * global[0] + offset[0]);
      if (s0 == static_cast<std::int64_t>(E)) {
        std::memcpy(dst, src, E * static_cast<std::size_t>(v.dims[0]));
      } else {
        for (std::int64_t i = 0; i < v.dims[0]; ++i) std::memcpy(dst + E * i, src + i * s0, E);
      }
    }
}

void copy_box(const FieldView& v, void* replica, const std::int64_t global[3], const std::int64_t offset[3]) {
  auto* dst = static_cast<unsigned char*>(replica);
  switch (dtype_size(v.dtype)) {
    case 1: copy_box_typed<1>(v, dst, global, offset); break;
    case 2: copy_box_typed<2>(v, dst, global, offset); break;
    case 4: copy_box_typed<4>(v, dst, global, offset); break;
    default: copy_box_typed<8>(v, dst, global, offset); break;
  }
}

/// Whole pixels of a Film (PixelSums, or with `bytes` = sizeof(AuxSums) its auxiliary sums),
/// moved as raw bytes (doubles and counters exactly as they are).
MPI_Datatype pixel_type(TypeList& keep, std::size_t bytes = sizeof(PixelSums)) {
  MPI_Datatype t;
  check(MPI_Type_contiguous(static_cast<int>(bytes), MPI_BYTE, &t), "MPI_Type_contiguous");
  return keep.commit(t);
}

/// The rows of the given tiles inside a width-wide Film, relative to its first pixel (of
/// `pixel_bytes` each: PixelSums, or AuxSums for the auxiliary sums).
MPI_Datatype tile_rows_type(const std::vector<Tile>& tiles, std::span<const int> indices, int width,
                            MPI_Datatype pixel, TypeList& keep, std::uint64_t& pixels,
                            std::size_t pixel_bytes = sizeof(PixelSums)) {
  std::vector<int> lengths;
  std::vector<MPI_Aint> displs;
  for (int t : indices) {
    const Tile& tile = tiles[t];
    for (int y = tile.y0; y < tile.y1; ++y) {
      lengths.push_back(tile.x1 - tile.x0);
      displs.push_back(static_cast<MPI_Aint>((static_cast<std::int64_t>(y) * width + tile.x0) *
                                             static_cast<std::int64_t>(pixel_bytes)));
      pixels += static_cast<std::uint64_t>(tile.x1 - tile.x0);
    }
  }
  MPI_Datatype t;
  check(MPI_Type_create_hindexed(static_cast<int>(lengths.size()), lengths.data(), displs.data(), pixel, &t),
        "MPI_Type_create_hindexed");
  return keep.commit(t);
}

bool film_is_empty(const Film& film) {
  for (const PixelSums& p : film.pixels())
    if (p.drawn != 0 || p.n != 0) return false;
  return true;
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

/// What each rank tells the others before an assemble: its box, dtype and whether its view
/// is usable (all int64 so that one MPI_Allgather moves it).
struct MpiParallelContext::RankBox {
  std::int64_t offset[3];
  std::int64_t dims[3];
  std::int64_t global[3];
  std::int64_t dtype;
  std::int64_t view_ok;
};

// ---------------------------------------------------------------------------------------
// Construction: parallel_context_mpi_setup.cpp

MpiParallelContext::~MpiParallelContext() {
  if (!m_mpi) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;  // too late to free anything; the process is ending
  free_replica();
  if (m_counter_win != MPI_WIN_NULL) {
    MPI_Win_unlock_all(m_counter_win);
    MPI_Win_free(&m_counter_win);
  }
  if (m_node != MPI_COMM_NULL) MPI_Comm_free(&m_node);
  if (m_comm != MPI_COMM_NULL) MPI_Comm_free(&m_comm);
}

// ---------------------------------------------------------------------------------------
// Small collectives

bool MpiParallelContext::agree(bool ok) {
  if (m_size == 1) return ok;
  int local = ok ? 1 : 0, all = 0;
  check(MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LAND, m_comm), "MPI_Allreduce");
  return all != 0;
}

std::pair<double, double> MpiParallelContext::range(double local_min, double local_max) {
  if (m_size == 1) return {local_min, local_max};
  const double local[2] = {local_min, -local_max};
  double global[2];
  check(MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, m_comm), "MPI_Allreduce");
  return {global[0], -global[1]};
}

std::uint64_t MpiParallelContext::bytes_moved() const {
  return m_report.assemble_bytes + m_report.render_bytes;
}

// ---------------------------------------------------------------------------------------
// Assembly

void MpiParallelContext::free_replica() {
  if (m_replica_win == MPI_WIN_NULL) return;
  MPI_Win_unlock_all(m_replica_win);
  MPI_Win_free(&m_replica_win);
  m_replica = nullptr;
  m_replica_bytes = 0;
}

void MpiParallelContext::ensure_replica(std::uint64_t bytes) {
  if (m_replica_win != MPI_WIN_NULL && bytes == m_replica_bytes) return;
  free_replica();
  // The leader allocates the whole replica; the others map the leader's segment.
  const MPI_Aint mine = m_node_rank == 0 ? static_cast<MPI_Aint>(bytes) : 0;
  void* base = nullptr;
  check(MPI_Win_allocate_shared(mine, 1, MPI_INFO_NULL, m_node, &base, &m_replica_win),
        "MPI_Win_allocate_shared");
  MPI_Win_set_errhandler(m_replica_win, MPI_ERRORS_RETURN);
  MPI_Aint size = 0;
  int disp_unit = 0;
  check(MPI_Win_shared_query(m_replica_win, 0, &size, &disp_unit, &m_replica), "MPI_Win_shared_query");
  m_replica_bytes = bytes;
  check(MPI_Win_lock_all(MPI_MODE_NOCHECK, m_replica_win), "MPI_Win_lock_all");
}

void MpiParallelContext::exchange_boxes(const FieldView& local, const std::vector<RankBox>& boxes) {
  const RankBox& me = boxes[m_rank];
  TypeList keep;
  std::vector<int> send_counts(m_size, 0), recv_counts(m_size, 0), zero(m_size, 0);
  std::vector<MPI_Datatype> send_types(m_size, MPI_BYTE), recv_types(m_size, MPI_BYTE);
  MPI_Request request = MPI_REQUEST_NULL;
  const std::uint64_t box_bytes = static_cast<std::uint64_t>(local.vertex_count()) * dtype_size(local.dtype);

  // Other nodes: my view, read in place, to each other node's leader, straight into the box
  // that the leader's receive type describes.
  if (m_node_count > 1) {
    const MPI_Datatype view = strided_view_type(local, keep);
    for (int d = 0; d < m_size; ++d)
      if (m_leader_of[d] == d && d != m_leader_of[m_rank]) {
        send_counts[d] = 1;
        send_types[d] = view;
        m_report.assemble_bytes += box_bytes;
      }
    if (m_node_rank == 0)
      for (int s = 0; s < m_size; ++s)
        if (m_leader_of[s] != m_rank) {
          recv_counts[s] = 1;
          recv_types[s] = replica_box_type(local.dtype, boxes[s].global, boxes[s].offset, boxes[s].dims, keep);
        }
    check(MPI_Ialltoallw(local.data, send_counts.data(), zero.data(), send_types.data(), m_replica,
                         recv_counts.data(), zero.data(), recv_types.data(), m_comm, &request),
          "MPI_Ialltoallw");
  }

  // This node: each rank writes its own box into the shared replica, all ranks at once.
  copy_box(local, m_replica, me.global, me.offset);
  m_report.assemble_bytes += box_bytes;

  if (request != MPI_REQUEST_NULL) check(MPI_Wait(&request, MPI_STATUS_IGNORE), "MPI_Wait");
}

FieldView MpiParallelContext::assemble(const FieldView& local, const GlobalPlacement& where) {
  m_report.assemble_bytes = 0;
  if (m_size == 1) {
    local.validate("field");
    for (int a = 0; a < 3; ++a)
      if (where.offset[a] != 0 || local.dims[a] != where.global_dims[a])
        throw std::runtime_error("one rank must hold the whole grid: its real vertices " +
                                 box_text(where.offset, local.dims) + " do not cover global dims " +
                                 std::to_string(where.global_dims[0]) + "x" +
                                 std::to_string(where.global_dims[1]) + "x" +
                                 std::to_string(where.global_dims[2]));
    return local;  // zero copy
  }

  // Everyone learns everyone's box; the checks below then fail alike on every rank.
  RankBox mine{};
  std::string view_error;
  try {
    local.validate("field");
  } catch (const std::exception& e) {
    view_error = e.what();
  }
  for (int a = 0; a < 3; ++a) {
    mine.offset[a] = where.offset[a];
    mine.dims[a] = local.dims[a];
    mine.global[a] = where.global_dims[a];
  }
  mine.dtype = static_cast<std::int64_t>(local.dtype);
  mine.view_ok = view_error.empty() ? 1 : 0;
  constexpr int kWords = sizeof(RankBox) / sizeof(std::int64_t);
  std::vector<RankBox> boxes(m_size);
  check(MPI_Allgather(&mine, kWords, MPI_INT64_T, boxes.data(), kWords, MPI_INT64_T, m_comm),
        "MPI_Allgather");

  // Check the decomposition: one dtype, one global grid, disjoint boxes covering it.
  const RankBox& first = boxes[0];
  std::int64_t covered = 0;
  for (int r = 0; r < m_size; ++r) {
    const RankBox& b = boxes[r];
    const std::string who = "rank " + std::to_string(r);
    if (!b.view_ok)
      throw std::runtime_error(r == m_rank ? view_error : who + " published an invalid field view");
    if (b.dtype != first.dtype)
      throw std::runtime_error("ranks publish different dtypes: rank 0 " +
                               std::string(dtype_name(static_cast<DType>(first.dtype))) + ", " + who +
                               " " + dtype_name(static_cast<DType>(b.dtype)));
    for (int a = 0; a < 3; ++a) {
      if (b.global[a] != first.global[a])
        throw std::runtime_error("ranks disagree on global_dims: rank 0 and " + who + " differ along axis " +
                                 std::to_string(a));
      if (b.global[a] < 1 || b.global[a] > INT_MAX)
        throw std::runtime_error("global_dims must be in [1, " + std::to_string(INT_MAX) + "]");
      if (b.offset[a] < 0 || b.dims[a] < 1 || b.offset[a] + b.dims[a] > b.global[a])
        throw std::runtime_error(who + "'s real vertices " + box_text(b.offset, b.dims) +
                                 " leave the global grid");
    }
    covered += b.dims[0] * b.dims[1] * b.dims[2];
    for (int q = 0; q < r; ++q) {
      const RankBox& o = boxes[q];
      bool overlap = true;
      for (int a = 0; a < 3; ++a)
        overlap = overlap && b.offset[a] < o.offset[a] + o.dims[a] && o.offset[a] < b.offset[a] + b.dims[a];
      if (overlap)
        throw std::runtime_error("rank " + std::to_string(q) + "'s real vertices " + box_text(o.offset, o.dims) +
                                 " overlap " + who + "'s " + box_text(b.offset, b.dims) +
                                 " (declare shared vertices as ghosts on all but one rank)");
    }
  }
  const std::int64_t total = first.global[0] * first.global[1] * first.global[2];
  if (covered != total)
    throw std::runtime_error("the ranks' real vertices cover " + std::to_string(covered) + " of the " +
                             std::to_string(total) + " global vertices");

  // Nobody on this node may still be reading the previous replica while it is overwritten.
  ensure_replica(static_cast<std::uint64_t>(total) * dtype_size(local.dtype));
  check(MPI_Barrier(m_node), "MPI_Barrier");
  exchange_boxes(local, boxes);
  // Publish the node's writes to every rank of the node.
  MPI_Win_sync(m_replica_win);
  check(MPI_Barrier(m_node), "MPI_Barrier");
  MPI_Win_sync(m_replica_win);
  return FieldView::contiguous(m_replica, local.dtype, first.global[0], first.global[1], first.global[2]);
}

// ---------------------------------------------------------------------------------------
// Rendering

void MpiParallelContext::render(const PreparedScene& scene, Film& film, RenderStats& stats) {
  m_report.render_bytes = 0;
  if (m_size > 1) {
    render_multi(scene, film, stats);
    return;
  }
  RenderStats local;
  const double cpu0 = process_cpu_seconds();
  tessera::render(scene, film, local);
  m_report.render_cpu_seconds = process_cpu_seconds() - cpu0;
  m_report.render_seconds = local.wall_seconds;
  m_report.tiles = static_cast<int>(scene.tiles().size());
  m_report.grabs = 1;
  m_report.chunk = m_report.tiles;
  stats.add_counters(local);
  stats.tiles_total += local.tiles_total;
  stats.wall_seconds += local.wall_seconds;
  stats.threads = local.threads;
}

void MpiParallelContext::render_multi(const PreparedScene& scene, Film& film, RenderStats& stats) {
  const std::vector<Tile>& tiles = scene.tiles();
  const int ntiles = static_cast<int>(tiles.size());
  const int width = scene.desc().image.width, height = scene.desc().image.height;
  TypeList keep;
  const MPI_Datatype pixel = pixel_type(keep);

  // Same image everywhere, and where its pixels start: rank 0's film is either empty (every
  // rank starts from zero) or holds earlier samples (every rank continues from them).
  enum : std::int64_t { kEmpty = 0, kContinue = 1, kWrongSize = 2 };
  std::int64_t head[6] = {width, height, ntiles, kEmpty, film.width(), film.height()};
  if (m_rank == 0 && (film.width() != width || film.height() != height)) head[3] = kWrongSize;
  else if (m_rank == 0 && !film_is_empty(film)) head[3] = kContinue;
  check(MPI_Bcast(head, 6, MPI_INT64_T, 0, m_comm), "MPI_Bcast");
  const bool same = head[0] == width && head[1] == height && head[2] == ntiles;
  if (!agree(same && head[3] != kWrongSize))
    throw std::runtime_error(head[3] == kWrongSize
                                 ? "rank 0's film is " + std::to_string(head[4]) + "x" + std::to_string(head[5]) +
                                       ", the image " + std::to_string(width) + "x" + std::to_string(height)
                                 : std::string("ranks prepared different images or tile lists"));
  if (film.width() != width || film.height() != height) film = Film(width, height, film.has_aux());
  // image.denoise: the auxiliary sums travel beside the pixels (every rank's film has them)
  const MPI_Datatype aux_pixel = film.has_aux() ? pixel_type(keep, sizeof(AuxSums)) : MPI_DATATYPE_NULL;
  if (head[3] == kEmpty) {
    if (m_rank != 0) film.clear();
  } else {
    check(MPI_Bcast(film.pixels().data(), width * height, pixel, 0, m_comm), "MPI_Bcast");
    if (film.has_aux()) check(MPI_Bcast(film.aux().data(), width * height, aux_pixel, 0, m_comm), "MPI_Bcast");
    if (m_rank == 0) m_report.render_bytes += film.pixels().size() * sizeof(PixelSums) * (m_size - 1);
  }

  // Reset the counter; nobody grabs before the reset is visible.
  if (m_rank == 0) {
    const std::int64_t zero = 0;
    check(MPI_Accumulate(&zero, 1, MPI_INT64_T, 0, 0, 1, MPI_INT64_T, MPI_REPLACE, m_counter_win),
          "MPI_Accumulate");
    check(MPI_Win_flush(0, m_counter_win), "MPI_Win_flush");
  }
  check(MPI_Barrier(m_comm), "MPI_Barrier");

  // Threads: `threads: 0` means all hardware threads of the node, shared by its ranks (unless
  // the launcher already bound this rank to fewer cores than the machine has).
  int threads = scene.desc().options.threads;
  if (threads <= 0) {
    threads = tbb::this_task_arena::max_concurrency();
    if (m_node_size > 1 && threads >= static_cast<int>(std::thread::hardware_concurrency()))
      threads = std::max(1, threads / m_node_size);
  }
  tbb::task_arena arena(threads);  // render_tiles uses the arena's concurrency

  // Grab a few tiles at a time until none is left. A chunk keeps this rank's threads busy
  // without letting one rank take a large share at the end.
  const int chunk = std::clamp(ntiles / (8 * m_size), 1, std::max(4, 2 * threads));
  const std::int64_t step = chunk;
  std::vector<int> mine;
  mine.reserve(static_cast<std::size_t>(ntiles / m_size + chunk));
  RenderStats local;
  std::string error;
  int grabs = 0;
  // tessera.time_limit: checked before each grab (and by render_tiles before each tile)
  const auto deadline = scene.desc().options.deadline;
  bool timed_out = false;
  std::int64_t tiles_done = 0;
  const auto grab_and_render = [&] {
    while (error.empty() && !timed_out) {
      if (std::chrono::steady_clock::now() >= deadline) {
        timed_out = true;
        return;
      }
      std::int64_t start = 0;
      check(MPI_Fetch_and_op(&step, &start, MPI_INT64_T, 0, 0, MPI_SUM, m_counter_win),
            "MPI_Fetch_and_op");
      check(MPI_Win_flush(0, m_counter_win), "MPI_Win_flush");
      if (start >= ntiles) return;
      const std::size_t first = mine.size();
      for (std::int64_t t = start; t < std::min<std::int64_t>(start + step, ntiles); ++t)
        mine.push_back(static_cast<int>(t));
      ++grabs;
      try {
        const std::span<const int> grabbed = std::span<const int>(mine).subspan(first);
        arena.execute([&] { render_tiles(scene, grabbed, film, local); });
        tiles_done += static_cast<std::int64_t>(grabbed.size());
      } catch (const DeadlineExceeded& e) {
        timed_out = true;
        tiles_done += static_cast<std::int64_t>(e.tiles_done());
      } catch (const std::exception& e) {
        error = "rank " + std::to_string(m_rank) + ": " + e.what();
      }
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_seconds();
  grab_and_render();  // MPI calls only from this thread (MPI_THREAD_FUNNELED)
  m_report.render_cpu_seconds = process_cpu_seconds() - cpu0;
  m_report.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m_report.tiles = static_cast<int>(mine.size());
  m_report.grabs = grabs;
  m_report.chunk = chunk;
  // One reduction, before the gather: ranks that failed, ranks cut short by the deadline and
  // the tiles finished, so every rank throws alike and none waits in the gather
  const std::int64_t mine_flags[3] = {error.empty() ? 0 : 1, timed_out ? 1 : 0, tiles_done};
  std::int64_t all_flags[3] = {};
  check(MPI_Allreduce(mine_flags, all_flags, 3, MPI_INT64_T, MPI_SUM, m_comm), "MPI_Allreduce");
  if (all_flags[0] > 0) throw std::runtime_error(error.empty() ? "rendering failed on another rank" : error);
  if (all_flags[1] > 0)
    throw DeadlineExceeded(static_cast<std::size_t>(all_flags[2]), static_cast<std::size_t>(ntiles));

  // Rank 0 learns who rendered what, then receives each rank's tile rows straight into place.
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(m_rank == 0 ? m_size : 0), displs(m_rank == 0 ? m_size : 0), all;
  check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, m_comm), "MPI_Gather");
  if (m_rank == 0) {
    int sum = 0;
    for (int r = 0; r < m_size; ++r) {
      displs[r] = sum;
      sum += counts[r];
    }
    all.resize(sum);
  }
  check(MPI_Gatherv(mine.data(), count, MPI_INT, all.data(), counts.data(), displs.data(), MPI_INT, 0, m_comm),
        "MPI_Gatherv");
  if (m_rank != 0) {
    m_report.render_bytes += mine.size() * sizeof(int);
    if (count > 0) {
      std::uint64_t pixels = 0;
      const MPI_Datatype rows = tile_rows_type(tiles, mine, width, pixel, keep, pixels);
      check(MPI_Send(film.pixels().data(), 1, rows, 0, kPixelTag, m_comm), "MPI_Send");
      m_report.render_bytes += pixels * sizeof(PixelSums);
      if (film.has_aux()) {
        std::uint64_t aux_pixels = 0;
        const MPI_Datatype aux_rows = tile_rows_type(tiles, mine, width, aux_pixel, keep, aux_pixels, sizeof(AuxSums));
        check(MPI_Send(film.aux().data(), 1, aux_rows, 0, kAuxTag, m_comm), "MPI_Send");
        m_report.render_bytes += aux_pixels * sizeof(AuxSums);
      }
    }
  } else {
    std::vector<MPI_Request> requests;
    for (int r = 1; r < m_size; ++r) {
      if (counts[r] == 0) continue;
      std::uint64_t pixels = 0;
      const std::span<const int> theirs(all.data() + displs[r], static_cast<std::size_t>(counts[r]));
      const MPI_Datatype rows = tile_rows_type(tiles, theirs, width, pixel, keep, pixels);
      requests.emplace_back();
      check(MPI_Irecv(film.pixels().data(), 1, rows, r, kPixelTag, m_comm, &requests.back()), "MPI_Irecv");
      if (film.has_aux()) {
        const MPI_Datatype aux_rows = tile_rows_type(tiles, theirs, width, aux_pixel, keep, pixels, sizeof(AuxSums));
        requests.emplace_back();
        check(MPI_Irecv(film.aux().data(), 1, aux_rows, r, kAuxTag, m_comm, &requests.back()), "MPI_Irecv");
      }
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
  }

  // Counters summed, wall time the slowest rank's, threads the total over ranks.
  constexpr int kCounters = 11;
  const std::uint64_t counters[kCounters] = {
      local.samples,         local.free_flight_lookups, local.transmittance_lookups,
      local.gradient_lookups, local.real_collisions,    local.null_collisions,
      local.discarded_samples, local.tiles_total,       local.tiles_skipped,
      static_cast<std::uint64_t>(local.threads), local.stalled_paths};
  std::uint64_t sums[kCounters] = {};
  check(MPI_Reduce(counters, sums, kCounters, MPI_UINT64_T, MPI_SUM, 0, m_comm), "MPI_Reduce");
  double slowest = 0.0;
  check(MPI_Reduce(&m_report.render_seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, m_comm), "MPI_Reduce");
  if (m_rank == 0) {
    RenderStats total;
    total.samples = sums[0];
    total.free_flight_lookups = sums[1];
    total.transmittance_lookups = sums[2];
    total.gradient_lookups = sums[3];
    total.real_collisions = sums[4];
    total.null_collisions = sums[5];
    total.discarded_samples = sums[6];
    total.tiles_skipped = sums[8];
    total.stalled_paths = sums[10];
    stats.add_counters(total);
    stats.tiles_total += sums[7];
    stats.threads = static_cast<int>(sums[9]);
    stats.wall_seconds += slowest;
  } else {
    stats.add_counters(local);
    stats.tiles_total += local.tiles_total;
    stats.threads = local.threads;
    stats.wall_seconds += m_report.render_seconds;
  }
}

}  // namespace tessera::insitu
