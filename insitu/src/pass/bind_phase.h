#pragma once
/// The bind phase: the call's descriptors -> zero-copy views of this rank's real elements of
/// the render's field (tessera_execute: one block on the grid; tessera_execute_domains: every
/// domain on the mesh), then, with refinement levels, every rank's boxes checked as one
/// hierarchy. Every fault is TESSERA_ERROR_DATA on every rank.
#include "data/amr_layout.h"
#include "data/field_binding.h"
#include "pass/field_device.h"
#include "pass/pass_context.h"

#include <tessera/magnitude_field.h>

#include <optional>
#include <string>
#include <vector>

namespace tessera::insitu {

/// The render's field as this rank holds it.
struct BoundField {
  FieldBinding binding;
  std::optional<AmrLayout> amr;  ///< refinement levels: every rank's boxes (empty: one level)
  std::string name;              ///< the simulation's name of the bound field (a magnitude: its field_key)
  /// `field: {magnitude: [...]}` on one rank holding the grid whole: the components, read in
  /// place (vector_binding.h); the binding is then component 0's.
  std::optional<MagnitudeField> magnitude;
  /// A magnitude otherwise: each block's magnitudes, which the binding's blocks view.
  std::vector<std::vector<double>> staged;
  /// Where the render traces and how the field gets there (device_phase.h).
  FieldDevice device;
};

/// Binds the field of pass.call.pub (a language binding's refusal stands in for this rank's
/// bind: its reason is the fault). Nothing when the ranks agreed on a failure (the gate's
/// outcome holds it).
std::optional<BoundField> bind_phase(PhaseGate& gate, const PassContext& pass);

}  // namespace tessera::insitu
