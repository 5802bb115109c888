// MpiParallelContext, the film: every rank starts from rank 0's film (empty, or the samples
// of a progressive render so far), and rank 0 receives every other rank's tile pixels.
#include "mpi/mpi_check.h"
#include "mpi/mpi_datatypes.h"
#include "mpi/parallel_context_mpi.h"

#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::insitu {
namespace {

using detail::check;

constexpr int kPixelTag = 0x7e55;
constexpr int kAuxTag = 0x7e56;  ///< image.denoise: the auxiliary sums, beside the pixels

bool film_is_empty(const Film& film) {
  for (const PixelSums& p : film.pixels())
    if (p.drawn != 0 || p.n != 0) return false;
  return true;
}

}  // namespace

void MpiParallelContext::share_film(const PreparedScene& scene, Film& film, MPI_Datatype pixel) {
  const int ntiles = static_cast<int>(scene.tiles().size());
  const int width = scene.desc().image.width, height = scene.desc().image.height;
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
  if (head[3] == kEmpty) {
    if (m_rank != 0) film.clear();
  } else {
    check(MPI_Bcast(film.pixels().data(), width * height, pixel, 0, m_comm), "MPI_Bcast");
    if (film.has_aux()) {  // image.denoise: every rank's film has them (same config)
      detail::TypeList keep;
      const MPI_Datatype aux_pixel = detail::pixel_type(keep, sizeof(AuxSums));
      check(MPI_Bcast(film.aux().data(), width * height, aux_pixel, 0, m_comm), "MPI_Bcast");
      if (m_rank == 0) m_report.render_bytes += film.aux().size() * sizeof(AuxSums) * (m_size - 1);
    }
    if (m_rank == 0) m_report.render_bytes += film.pixels().size() * sizeof(PixelSums) * (m_size - 1);
  }
}

void MpiParallelContext::gather_film(const std::vector<Tile>& tiles, const std::vector<int>& mine, int width,
                                     MPI_Datatype pixel, Film& film) {
  detail::TypeList keep;
  // image.denoise: the auxiliary sums travel beside the pixels (every rank's film has them)
  const MPI_Datatype aux_pixel = film.has_aux() ? detail::pixel_type(keep, sizeof(AuxSums)) : MPI_DATATYPE_NULL;
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
      const MPI_Datatype rows = detail::tile_rows_type(tiles, mine, width, pixel, keep, pixels);
      check(MPI_Send(film.pixels().data(), 1, rows, 0, kPixelTag, m_comm), "MPI_Send");
      m_report.render_bytes += pixels * sizeof(PixelSums);
      if (film.has_aux()) {
        std::uint64_t aux_pixels = 0;
        const MPI_Datatype aux_rows =
            detail::tile_rows_type(tiles, mine, width, aux_pixel, keep, aux_pixels, sizeof(AuxSums));
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
      const MPI_Datatype rows = detail::tile_rows_type(tiles, theirs, width, pixel, keep, pixels);
      requests.emplace_back();
      check(MPI_Irecv(film.pixels().data(), 1, rows, r, kPixelTag, m_comm, &requests.back()), "MPI_Irecv");
      if (film.has_aux()) {
        std::uint64_t aux_pixels = 0;
        const MPI_Datatype aux_rows =
            detail::tile_rows_type(tiles, theirs, width, aux_pixel, keep, aux_pixels, sizeof(AuxSums));
        requests.emplace_back();
        check(MPI_Irecv(film.aux().data(), 1, aux_rows, r, kAuxTag, m_comm, &requests.back()), "MPI_Irecv");
      }
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
  }
}

}  // namespace tessera::insitu
