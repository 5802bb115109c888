// ParallelContext without MPI: one rank, every collective is the identity.
#include "block_layout.h"
#include "block_ops.h"
#include "parallel_context.h"

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::insitu {
namespace {

class SerialContext final : public ParallelContext {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void connect() override {}
  bool agree(bool ok) override { return ok; }
  bool any(bool flag) override { return flag; }
  int min(int value) override { return value; }
  std::pair<double, double> range(double local_min, double local_max) override { return {local_min, local_max}; }
  void allgather(const void* mine, std::size_t bytes, void* all) override {
    if (bytes > 0) std::memcpy(all, mine, bytes);
  }
  void broadcast(std::string&, int) override {}

  FieldView assemble_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3], DType dtype) override {
    // tessera_execute's one block: the whole grid, zero copy (its own message)
    if (blocks.size() == 1 && blocks[0].domain < 0) {
      const FieldView& local = blocks[0].view;
      const std::int64_t* offset = blocks[0].offset;
      for (int a = 0; a < 3; ++a)
        if (offset[a] != 0 || local.dims[a] != global[a])
          throw LayoutError("one rank must hold the whole grid: real vertices " + std::to_string(local.dims[0]) + "x" +
                            std::to_string(local.dims[1]) + "x" + std::to_string(local.dims[2]) + " at offset (" +
                            std::to_string(offset[0]) + ", " + std::to_string(offset[1]) + ", " +
                            std::to_string(offset[2]) + ") do not cover global_dims " + std::to_string(global[0]) +
                            "x" + std::to_string(global[1]) + "x" + std::to_string(global[2]));
      return local;
    }
    check(blocks, global);
    if (blocks.size() == 1) return blocks[0].view;  // one domain covering the mesh: zero copy
    // Several domains: a replica, kept while its size is unchanged
    const std::size_t bytes = static_cast<std::size_t>(global[0] * global[1] * global[2]) * dtype_size(dtype);
    if (m_replica.size() != bytes) {
      m_replica.clear();
      m_replica.shrink_to_fit();
      m_replica.resize(bytes);
    }
    for (const FieldBlock& b : blocks) copy_block(b.view, m_replica.data(), global, b.offset);
    return FieldView::contiguous(m_replica.data(), dtype, global[0], global[1], global[2]);
  }

  std::shared_ptr<const FieldSummary> summarize_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                                       DType dtype, int edge) override {
    if (blocks.size() == 1 && blocks[0].domain < 0) {
      const FieldView local = assemble_blocks(blocks, global, dtype);  // the checks of one rank
      return FieldSummary::build(local, edge);
    }
    check(blocks, global);
    FieldSummary::Parts parts = partial_of_blocks(blocks, global, edge);
    return FieldSummary::from_parts(std::move(parts), FieldLayout::of(blocks[0].view), edge);
  }
  PagedField distribute_blocks(std::span<const FieldBlock>, const std::int64_t*, DType, int, std::size_t) override {
    // The adapter renders one rank in replicated mode: its block is the whole field
    throw std::logic_error("distributed mode needs more than one rank");
  }
  void serve_while(const std::function<void()>& fn) override { fn(); }

  void render(const PreparedScene& scene, Film& film, RenderStats& stats) override {
    tessera::render(scene, film, stats);
  }

  std::uint64_t bytes_moved() const override { return 0; }

 private:
  /// The blocks tile the grid (block_layout.h); a rank without blocks cannot.
  static void check(std::span<const FieldBlock> blocks, const std::int64_t global[3]) {
    std::vector<BlockRecord> records(blocks.size());
    for (std::size_t n = 0; n < blocks.size(); ++n) {
      for (int a = 0; a < 3; ++a) {
        records[n].offset[a] = blocks[n].offset[a];
        records[n].dims[a] = blocks[n].view.dims[a];
      }
      records[n].rank = 0;
      records[n].domain = blocks[n].domain;
    }
    check_tiling(records, global, "elements");
  }

  std::vector<unsigned char> m_replica;  ///< several domains on one rank: their copy
};

}  // namespace

std::unique_ptr<ParallelContext> ParallelContext::create(int comm_f) {
  if (comm_f != -1)
    throw std::invalid_argument("Tessera was built without MPI: pass -1 as the communicator "
                                "(got " +
                                std::to_string(comm_f) + ")");
  return std::make_unique<SerialContext>();
}

}  // namespace tessera::insitu
