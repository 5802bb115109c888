// ParallelContext without MPI: one rank, every collective is the identity.
#include "parallel_context.h"

#include <cstring>
#include <stdexcept>
#include <string>

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

  FieldView assemble(const FieldView& local, const GlobalPlacement& where) override {
    for (int a = 0; a < 3; ++a)
      if (where.offset[a] != 0 || local.dims[a] != where.global_dims[a])
        throw LayoutError("one rank must hold the whole grid: real vertices " + std::to_string(local.dims[0]) + "x" +
                          std::to_string(local.dims[1]) + "x" + std::to_string(local.dims[2]) + " at offset (" +
                          std::to_string(where.offset[0]) + ", " + std::to_string(where.offset[1]) + ", " +
                          std::to_string(where.offset[2]) + ") do not cover global_dims " +
                          std::to_string(where.global_dims[0]) + "x" + std::to_string(where.global_dims[1]) + "x" +
                          std::to_string(where.global_dims[2]));
    return local;
  }

  std::shared_ptr<const FieldSummary> summarize(const FieldView& local, const GlobalPlacement& where,
                                                int edge) override {
    assemble(local, where);
    return FieldSummary::build(local, edge);
  }
  PagedField distribute(const FieldView&, const GlobalPlacement&, int, std::size_t) override {
    // The adapter renders one rank in replicated mode: its block is the whole field
    throw std::logic_error("distributed mode needs more than one rank");
  }
  void serve_while(const std::function<void()>& fn) override { fn(); }

  void render(const PreparedScene& scene, Film& film, RenderStats& stats) override {
    tessera::render(scene, film, stats);
  }

  std::uint64_t bytes_moved() const override { return 0; }
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
