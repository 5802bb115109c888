#include "outputs/triggers.h"

#include <algorithm>

namespace tessera::insitu {

Trigger::Trigger(const std::optional<config::TriggerSpec>& spec) {
  if (!spec) return;
  switch (spec->kind) {
    case config::TriggerSpec::Kind::Every:
      m_kind = Kind::Every;
      m_every = spec->every;
      break;
    case config::TriggerSpec::Kind::At:
      m_kind = Kind::At;
      m_at = spec->at;
      std::sort(m_at.begin(), m_at.end());
      m_at.erase(std::unique(m_at.begin(), m_at.end()), m_at.end());
      break;
    case config::TriggerSpec::Kind::When:
      m_kind = Kind::When;
      m_above = spec->above;
      break;
  }
}

bool Trigger::fires_on_step(std::int64_t step) const {
  switch (m_kind) {
    case Kind::Always: return true;
    case Kind::Every: return step % m_every == 0;
    case Kind::At: return std::binary_search(m_at.begin(), m_at.end(), step);
    case Kind::When:
    default: return false;
  }
}

}  // namespace tessera::insitu
