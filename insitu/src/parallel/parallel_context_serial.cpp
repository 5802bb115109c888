// ParallelContext without MPI: one rank, every collective is the identity.
#include "data/amr_layout.h"
#include "data/block_ops.h"
#include "parallel/parallel_context.h"

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
    return assemble_one_rank(blocks, global, dtype, m_replica);
  }
  AmrLayout amr_layout(std::span<const FieldBlock> blocks, const AmrField& meta, Association assoc) override {
    return amr_layout_one_rank(blocks, meta, assoc);
  }
  std::vector<AmrPatch> assemble_amr(std::span<const FieldBlock> blocks, const AmrLayout& layout) override {
    return patches_in_place(in_domain_order(blocks), layout);  // one rank: zero copy
  }
  std::shared_ptr<const FieldSummary> summarize_blocks(std::span<const FieldBlock> blocks, const std::int64_t global[3],
                                                       DType dtype, int edge) override {
    return summarize_one_rank(blocks, global, dtype, edge);
  }
  PagedField distribute_blocks(std::span<const FieldBlock>, const std::int64_t*, DType, int, std::size_t) override {
    // The adapter renders one rank in replicated mode: its block is the whole field
    throw std::logic_error("distributed mode needs more than one rank");
  }
  PagedField distribute_amr(std::span<const FieldBlock>, std::span<const BlockRecord>, const std::int64_t*, DType, int,
                            std::size_t) override {
    throw std::logic_error("distributed mode needs more than one rank");
  }
  void reduce_parts(FieldSummary::Parts&) override {}  // one rank: its parts are the whole's
  void serve_while(const std::function<void()>& fn) override { fn(); }

  void render(const PreparedScene& scene, Film& film, RenderStats& stats) override {
    tessera::render(scene, film, stats);
  }

  std::uint64_t bytes_moved() const override { return 0; }

 private:
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
