// The Cinema phase of a render (cinema_phase.h).
#include "pass/cinema_phase.h"

#include "outputs/outputs.h"
#include "pass/render_phase.h"
#include "pass/write_phase.h"

#include <tessera/image_format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace tessera::insitu {

bool cinema_phase(PhaseGate& gate, const PassContext& pass, const BoundField& field, PlacedField& placed,
                  const SceneSetup& setup, RenderResult& result) {
  const bool root = pass.root();
  const config::RenderSpec& spec = pass.spec;
  RenderState& render = pass.render;
  const std::string dir = (std::filesystem::path(pass.cfg.global.output_dir) / (spec.name + ".cdb")).string();
  if (root && !render.cinema) render.cinema = std::make_unique<CinemaDatabase>(dir);
  for (const CinemaView& view : setup.views) {
    PreparedScene prepared;
    if (!gate.run(TESSERA_ERROR_RENDER, [&] {
          SceneDesc s = setup.scene;
          s.camera = view.camera;
          prepared = prepare_scene(pass, field, placed, s, result);
        }))
      return false;
    std::optional<Image> img = render_phase(gate, pass, prepared, result);
    if (!img) return false;
    if (!gate.run(TESSERA_ERROR_IO, [&] {
          if (!root) return;
          const std::string rel = cinema_file_base(spec, pass.call.step, pass.call.time, view);
          const std::size_t first = result.files.size();
          const std::optional<AnnotationDesc> notes = annotations_of(pass, setup.scene);
          write_image_files((std::filesystem::path(dir) / rel).string(), spec.output, *img, result.files,
                            notes ? &*notes : nullptr);
          // FILE column: the file Cinema viewers show as it is (the PNG) when written, else
          // the first; write_image_files appended one file per format, in formats' order
          const std::vector<ImageFormat>& formats = spec.output.formats;
          std::string shown = result.files[first];
          for (std::size_t k = 0; k < formats.size(); ++k)
            if (image_format(formats[k]).shown_as_is) shown = result.files[first + k];
          render.cinema->set_row(pass.call.time, view.phi, view.theta,
                                 std::filesystem::path(shown).lexically_relative(dir).string());
        }))
      return false;
  }
  return gate.run(TESSERA_ERROR_IO, [&] {
    if (root) render.cinema->write();
  });
}

}  // namespace tessera::insitu
