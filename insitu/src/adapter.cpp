// tessera::insitu::Adapter: the public C++ class, forwarding to Adapter::Impl; adds the
// `on_error: abort` rethrow, which the C API leaves out.
#include <tessera/adapter.h>

#include "adapter_impl.h"

namespace tessera::insitu {

Adapter::Adapter() : m_impl(std::make_unique<Impl>()) {}
Adapter::~Adapter() {
  if (m_impl) m_impl->close();
}
Adapter::Adapter(Adapter&&) noexcept = default;
Adapter& Adapter::operator=(Adapter&&) noexcept = default;

tessera_status Adapter::open(const std::string& yaml_path, int mpi_comm_f) {
  if (!m_impl) m_impl = std::make_unique<Impl>();  // moved from: a fresh adapter
  return m_impl->open(yaml_path.c_str(), mpi_comm_f, nullptr);
}

tessera_status Adapter::open(const std::string& yaml_path, int mpi_comm_f, const OpenOptions& options) {
  if (!m_impl) m_impl = std::make_unique<Impl>();
  return m_impl->open(yaml_path.c_str(), mpi_comm_f, options.output_dir.c_str(),
                      options.yaml_text.empty() ? nullptr : &options.yaml_text);
}

tessera_status Adapter::execute(std::int64_t step, double time, const tessera_grid& grid,
                                std::span<const tessera_field> fields, bool final_step) {
  if (!m_impl) return TESSERA_ERROR_CONFIG;  // moved from
  const tessera_status s = m_impl->execute(step, time, &grid, fields.data(),
                                           static_cast<std::int64_t>(fields.size()), final_step);
  if (s != TESSERA_OK && m_impl->abort_mode()) throw AdapterError(s, m_impl->m_error);
  return s;
}

tessera_status Adapter::field_unchanged(const std::string& field_name) noexcept {
  return m_impl ? m_impl->field_unchanged(field_name.c_str()) : TESSERA_ERROR_CONFIG;
}

tessera_status Adapter::close() noexcept {
  if (!m_impl) return TESSERA_OK;  // moved from
  m_impl->close();
  m_impl->m_error.clear();
  return TESSERA_OK;
}

bool Adapter::is_open() const noexcept { return m_impl && m_impl->m_ctx != nullptr; }
const std::string& Adapter::last_error() const noexcept {
  static const std::string moved = "adapter was moved from";
  return m_impl ? m_impl->m_error : moved;
}
const std::vector<RenderResult>& Adapter::last_results() const noexcept { return m_impl->m_results; }

const Image* Adapter::last_image(const std::string& name) const noexcept {
  for (const RenderState& r : m_impl->m_renders)
    if (r.spec->name == name) return r.last_image ? &*r.last_image : nullptr;
  return nullptr;
}

void Adapter::set_quiet(bool quiet) noexcept { m_impl->m_quiet = quiet; }

}  // namespace tessera::insitu
