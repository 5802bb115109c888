#include "outputs/cinema.h"

#include "outputs/outputs.h"

#include <tessera/config/build_scene.h>
#include <tessera/config/output_path.h>
#include <tessera/number_text.h>
#include <tessera/regular_file.h>

#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace tessera::insitu {
namespace {

constexpr const char* kHeader = "time,phi,theta,FILE";

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

/// Splits one CSV line into fields (quotes as written by csv_field).
std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else out.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  return out;
}

}  // namespace

std::vector<CinemaView> cinema_views(const config::CinemaSpec& spec, const CameraDesc& main,
                                     const Bounds& data_bounds) {
  const Vec3 centre = data_bounds.center();
  const double distance = glm::length(main.position - centre);
  if (!(distance > 0.0))
    throw std::invalid_argument("cinema: the render's camera sits at the data centre, so the "
                                "orbit distance is 0");
  // An empty list stands for the single angle 0
  static const std::vector<double> kZero{0.0};
  const std::vector<double>& phis = spec.azimuths.empty() ? kZero : spec.azimuths;
  const std::vector<double>& thetas = spec.elevations.empty() ? kZero : spec.elevations;
  std::vector<CinemaView> views;
  for (const double theta : thetas)
    for (const double phi : phis) {
      CinemaView v;
      v.phi = phi;
      v.theta = theta;
      v.camera = main;
      v.camera.look_at = centre;
      v.camera.position = centre + distance * config::orbit_direction(config::OrbitSpec{phi, theta, 1.0}, main.up);
      v.camera.up = config::orbit_direction(config::OrbitSpec{phi, theta + 90.0, 1.0}, main.up);
      views.push_back(v);
    }
  return views;
}

std::string cinema_file_base(const config::RenderSpec& spec, std::int64_t step, double time, const CinemaView& view) {
  return config::format_output_path(spec.output.file, spec.name, step, time, 0) + "_phi_" + format_number(view.phi) +
         "_theta_" + format_number(view.theta);
}

void CinemaDatabase::load_existing() {
  m_loaded = true;
  // Read through RegularFile: a FIFO or a device named data.csv is refused without blocking
  const std::string path = (std::filesystem::path(m_dir) / "data.csv").string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return;
  const RegularFile file(path);
  std::string text(static_cast<std::size_t>(file.size()), '\0');
  file.read_at(0, text.data(), text.size());
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) return;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> f = csv_split(line);
    if (f.size() == 4) m_rows.push_back(Row{f[0], f[1], f[2], f[3]});
  }
}

void CinemaDatabase::set_row(double time, double phi, double theta, const std::string& file) {
  if (!m_loaded) load_existing();
  Row row{format_number(time), format_number(phi), format_number(theta), file};
  for (Row& r : m_rows)
    if (r.file == file) {
      r = std::move(row);
      return;
    }
  m_rows.push_back(std::move(row));
}

void CinemaDatabase::write() const {
  std::string text = std::string(kHeader) + "\n";
  for (const Row& r : m_rows)
    text += csv_field(r.time) + "," + csv_field(r.phi) + "," + csv_field(r.theta) + "," + csv_field(r.file) + "\n";
  write_text_atomic((std::filesystem::path(m_dir) / "data.csv").string(), text);
}

}  // namespace tessera::insitu
