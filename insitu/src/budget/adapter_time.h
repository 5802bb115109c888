#pragma once
/// The seconds spent inside the execute calls of every adapter of this process, as one
/// running sum. An adapter measures the simulation's time as the wall time between its own
/// calls less what the other adapters spent meanwhile (adapter_time_total() then minus
/// adapter_time_total() before), so that a render budget never counts another adapter's
/// rendering as simulation. Thread-safe, lock-free.

namespace tessera::insitu {

/// Adds one execute call's seconds (>= 0; anything else adds nothing).
void add_adapter_time(double seconds) noexcept;

/// The sum so far (seconds, from 0 at the start of the process).
double adapter_time_total() noexcept;

}  // namespace tessera::insitu
