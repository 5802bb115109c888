#pragma once
/// One render over curvilinear and unstructured domains (tessera_execute_mesh_domains), as
/// its phases: bind (descriptors, then check_mesh of this rank's domains, then the ranks agree
/// on the field's dtype and association), extent (the mesh's bounds and cells over the
/// ranks), range (`range: auto` and `when` triggers), plan (memory; replicated only), gather
/// (several ranks: every rank's domains on every rank; one rank: in place), then the scene,
/// prepare(Mesh), render and write phases of a grid's render. The mesh is checked once per
/// call: prepare takes bind's receipt (MeshChecked), or on several ranks check_mesh_copy's
/// of the gathered copies. Every fault is agreed on by every rank (PhaseGate); none hangs.
#include "pass/pass_context.h"

namespace tessera::insitu {

/// The render of pass.call.pub's mesh domains into `out` (begun; `gate` is over it).
/// check_when: the render fires only if its `when` trigger does.
void run_mesh(const PassContext& pass, PhaseGate& gate, PassOutcome& out, bool check_when, bool quiet);

}  // namespace tessera::insitu
