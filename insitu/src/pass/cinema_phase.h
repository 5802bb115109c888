#pragma once
/// The Cinema phase (output.cinema): per view of the sweep, the scene prepared with the view's
/// camera, rendered and written into the render's Cinema database (NAME.cdb under output_dir,
/// one row per view: time, phi, theta, file), then the database's data.csv (rank 0).
#include "pass/prepare_phase.h"

#include <tessera/adapter.h>

#include <vector>

namespace tessera::insitu {

/// False when the ranks agreed on a failure (in any view's prepare, render or write).
bool cinema_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field, PlacedField& placed,
                  const SceneSetup& setup, RenderResult& result);

}  // namespace tessera::insitu
