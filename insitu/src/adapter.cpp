// tessera::insitu::Adapter: the public C++ class, forwarding to Adapter::Impl; adds the
// `on_error: abort` rethrow, which the C API leaves out.
#include <tessera/adapter.h>

#include "adapter_impl.h"
#include "agreement/call_gate.h"

namespace tessera::insitu {

namespace {

/// The refused call's status, with its message kept for this thread's last_error().
tessera_status refuse(const void* owner, CallGate::Refusal refusal, const char* function) noexcept {
  try {
    note_refusal(owner, refusal_message(refusal, function));
  } catch (...) {
  }
  return TESSERA_ERROR_CONFIG;
}

}  // namespace

Adapter::Adapter() : m_impl(std::make_unique<Impl>()) {}
Adapter::~Adapter() {
  if (!m_impl) return;
  m_impl->m_gate.begin_close();  // a call still inside (another thread) finishes first
  m_impl->close();
  m_impl->m_gate.end_close();
}
Adapter::Adapter(Adapter&&) noexcept = default;
Adapter& Adapter::operator=(Adapter&&) noexcept = default;

tessera_status Adapter::open(const std::string& yaml_path, int mpi_comm_f) {
  return open(yaml_path, mpi_comm_f, OpenOptions{});
}

tessera_status Adapter::open(const std::string& yaml_path, int mpi_comm_f, const OpenOptions& options) {
  if (!m_impl) m_impl = std::make_unique<Impl>();  // moved from: a fresh adapter
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None) return refuse(m_impl.get(), inside.refusal(), "open");
  clear_refusal(m_impl.get());
  return m_impl->open(yaml_path.c_str(), mpi_comm_f, options.output_dir.c_str(),
                      options.yaml_text.empty() ? nullptr : &options.yaml_text);
}

tessera_status Adapter::execute(std::int64_t step, double time, const tessera_grid& grid,
                                std::span<const tessera_field> fields, bool final_step) {
  if (!m_impl) return TESSERA_ERROR_CONFIG;  // moved from
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None)
    return refuse(m_impl.get(), inside.refusal(), final_step ? "execute (final step)" : "execute");
  clear_refusal(m_impl.get());
  const tessera_status s =
      m_impl->execute(step, time, &grid, fields.data(), static_cast<std::int64_t>(fields.size()), final_step);
  if (s != TESSERA_OK && m_impl->abort_mode()) throw AdapterError(s, m_impl->m_error);
  return s;
}

tessera_status Adapter::execute_domains(std::int64_t step, double time, const tessera_mesh& mesh,
                                        std::span<const tessera_domain> domains, bool final_step) {
  if (!m_impl) return TESSERA_ERROR_CONFIG;  // moved from
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None)
    return refuse(m_impl.get(), inside.refusal(), final_step ? "execute_domains (final step)" : "execute_domains");
  clear_refusal(m_impl.get());
  const tessera_status s =
      m_impl->execute_domains(step, time, &mesh, domains.data(), static_cast<std::int64_t>(domains.size()), final_step);
  if (s != TESSERA_OK && m_impl->abort_mode()) throw AdapterError(s, m_impl->m_error);
  return s;
}

tessera_status Adapter::execute_mesh_domains(std::int64_t step, double time,
                                             std::span<const tessera_mesh_domain> domains, bool final_step) {
  if (!m_impl) return TESSERA_ERROR_CONFIG;  // moved from
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None)
    return refuse(m_impl.get(), inside.refusal(),
                  final_step ? "execute_mesh_domains (final step)" : "execute_mesh_domains");
  clear_refusal(m_impl.get());
  const tessera_status s =
      m_impl->execute_mesh_domains(step, time, domains.data(), static_cast<std::int64_t>(domains.size()), final_step);
  if (s != TESSERA_OK && m_impl->abort_mode()) throw AdapterError(s, m_impl->m_error);
  return s;
}

tessera_status Adapter::field_unchanged(const std::string& field_name) noexcept {
  if (!m_impl) return TESSERA_ERROR_CONFIG;
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None) return refuse(m_impl.get(), inside.refusal(), "field_unchanged");
  clear_refusal(m_impl.get());
  return m_impl->field_unchanged(field_name.c_str());
}

tessera_status Adapter::execute_refused(std::int64_t step, double time, int call_kind, const std::string& reason,
                                        bool final_step) {
  if (!m_impl) return TESSERA_ERROR_CONFIG;  // moved from
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None) return refuse(m_impl.get(), inside.refusal(), "execute_refused");
  clear_refusal(m_impl.get());
  const std::string why = reason.empty() ? "the language binding refused this rank's arguments" : reason;
  const tessera_status s = m_impl->execute_refused(step, time,
                                                   call_kind == 2   ? 2
                                                   : call_kind == 1 ? 1
                                                                    : 0,
                                                   why.c_str(), final_step);
  if (s != TESSERA_OK && m_impl->abort_mode()) throw AdapterError(s, m_impl->m_error);
  return s;
}

tessera_status Adapter::mesh_unchanged() noexcept {
  if (!m_impl) return TESSERA_ERROR_CONFIG;
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None) return refuse(m_impl.get(), inside.refusal(), "mesh_unchanged");
  clear_refusal(m_impl.get());
  return m_impl->mesh_unchanged();
}

tessera_status Adapter::set_cuda_stream(void* cuda_stream) noexcept {
  if (!m_impl) return TESSERA_ERROR_CONFIG;
  GateCall inside(m_impl->m_gate);
  if (inside.refusal() != CallGate::Refusal::None) return refuse(m_impl.get(), inside.refusal(), "set_cuda_stream");
  clear_refusal(m_impl.get());
  return m_impl->set_cuda_stream(cuda_stream);
}

tessera_status Adapter::close() noexcept {
  if (!m_impl) return TESSERA_OK;  // moved from
  m_impl->m_gate.begin_close();    // waits for a call inside; refuses new ones meanwhile
  clear_refusal(m_impl.get());
  const bool was_open = m_impl->m_ctx != nullptr;
  const tessera_status s = m_impl->close();
  if (s == TESSERA_OK || !was_open) m_impl->m_error.clear();
  m_impl->m_gate.end_close();
  return s;
}

bool Adapter::fires(std::int64_t step, bool final_step) const noexcept {
  return m_impl && m_impl->m_ctx && m_impl->any_fires(step, final_step);
}

bool Adapter::is_open() const noexcept { return m_impl && m_impl->m_ctx != nullptr; }
const std::string& Adapter::last_error() const noexcept {
  static const std::string moved = "adapter was moved from";
  if (!m_impl) return moved;
  if (const std::string* refused = refusal_for(m_impl.get())) return *refused;
  return m_impl->m_error;
}
const std::vector<RenderResult>& Adapter::last_results() const noexcept { return m_impl->m_results; }

const Image* Adapter::last_image(const std::string& name) const noexcept {
  for (const RenderState& r : m_impl->m_renders)
    if (r.spec->name == name) return r.last_image ? &*r.last_image : nullptr;
  return nullptr;
}

void Adapter::set_quiet(bool quiet) noexcept { m_impl->m_quiet = quiet; }

}  // namespace tessera::insitu
