// The write phase of a render (write_phase.h).
#include "pass/write_phase.h"

#include "outputs/outputs.h"

#include <tessera/config/annotations.h>

#include <utility>

namespace tessera::insitu {

std::optional<AnnotationDesc> annotations_of(const PassContext& pass, const SceneDesc& scene) {
  const config::RenderSpec& spec = pass.spec;
  if (!spec.annotations) return std::nullopt;
  return config::build_annotations(*spec.annotations, spec.name, spec.field, scene.tf, pass.call.step, pass.call.time);
}

bool write_phase(PhaseGate& gate, const PassContext& pass, const SceneDesc& scene, Image img, RenderResult& result) {
  return gate.run(TESSERA_ERROR_IO, [&] {
    if (!pass.root()) return;
    const std::optional<AnnotationDesc> notes = annotations_of(pass, scene);
    write_image_files(output_base(pass.cfg.global.output_dir, pass.spec, pass.call.step, pass.call.time, 0),
                      pass.spec.output, img, result.files, notes ? &*notes : nullptr);
    pass.render.last_image = std::move(img);
  });
}

}  // namespace tessera::insitu
