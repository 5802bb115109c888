#pragma once
/// Cinema image databases (Cinema Spec D): a render with `output: {cinema: {azimuth: [...],
/// elevation: [...]}}` (config::CinemaSpec, degrees) also renders an orbit of azimuth x
/// elevation cameras about the data centre into output_dir/<name>.cdb/, indexed by data.csv
/// with the columns time,phi,theta,FILE.
#include <tessera/camera.h>
#include <tessera/config/render_spec.h>
#include <tessera/scene.h>

#include <string>
#include <vector>

namespace tessera::insitu {

/// One camera of the sweep; phi (azimuth) and theta (elevation) in degrees as configured.
struct CinemaView {
  double phi = 0.0;
  double theta = 0.0;
  CameraDesc camera;
};

/// The cameras, elevation-major (phi fastest). Each looks at the data centre from
/// centre + d * orbit_direction(phi, theta, up) (build_scene.h), d = the render's camera
/// distance from that centre (a moving orbit's at the call's step; phi and theta stay absolute,
/// so each names the same view at every step), with the render's fov, aperture and focus distance. Its up is
/// the direction of (phi, theta + 90): perpendicular to the view, and the render's `up`
/// projected onto the image plane wherever that is defined, so that the poles (theta = +-90)
/// render too. An empty azimuth or elevation list stands for [0]. Throws std::invalid_argument if the render's camera sits at the centre.
std::vector<CinemaView> cinema_views(const config::CinemaSpec& spec, const CameraDesc& main, const Bounds& data_bounds);

/// The image file name of one view, relative to the database directory, without extension:
/// the render's output pattern followed by _phi_<phi>_theta_<theta>.
std::string cinema_file_base(const config::RenderSpec& spec, std::int64_t step, double time, const CinemaView& view);

/// data.csv of one database. Rows persist across timesteps (and across runs: an existing
/// data.csv with the same columns is read back first); a row for a FILE already listed
/// replaces it. set_row() throws std::runtime_error naming the file when an existing data.csv
/// is not a regular file (a FIFO is refused without blocking). Not thread-safe; rank 0 only.
class CinemaDatabase {
 public:
  explicit CinemaDatabase(std::string dir) : m_dir(std::move(dir)) {}
  const std::string& dir() const { return m_dir; }

  void set_row(double time, double phi, double theta, const std::string& file);
  /// Rewrites dir/data.csv atomically. Throws std::runtime_error naming the file.
  void write() const;

 private:
  struct Row {
    std::string time, phi, theta, file;
  };
  void load_existing();

  std::string m_dir;
  bool m_loaded = false;
  std::vector<Row> m_rows;
};

}  // namespace tessera::insitu
