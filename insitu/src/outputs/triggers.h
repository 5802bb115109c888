#pragma once
/// Trigger: when one render fires, decided from the step alone where possible so that a call
/// where nothing fires touches no field memory.
#include <tessera/config/render_spec.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace tessera::insitu {

class Trigger {
 public:
  /// Absent spec: fires every step.
  explicit Trigger(const std::optional<config::TriggerSpec>& spec);

  /// True if deciding needs the global field maximum (`when: {above: X}`).
  bool needs_field_max() const { return m_kind == Kind::When; }
  /// Step-only decision for `every` and `at`; must not be called when needs_field_max().
  bool fires_on_step(std::int64_t step) const;
  /// `when`: fires iff the global maximum of the field's finite values exceeds `above`.
  bool fires_on_max(double field_max) const { return field_max > m_above; }

 private:
  enum class Kind { Always, Every, At, When };
  Kind m_kind = Kind::Always;
  std::int64_t m_every = 1;
  std::vector<std::int64_t> m_at;  ///< sorted, unique
  double m_above = 0.0;
};

}  // namespace tessera::insitu
