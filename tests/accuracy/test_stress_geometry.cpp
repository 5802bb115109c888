// Stress: extreme geometry (docs/accuracy.md, "Stress"). Finite pixels, nothing discarded,
// and the right answer where one is known:
//  - one vertex along an axis (no thickness: the background exactly, no lookups), two
//    vertices (a one-voxel slab) and a 2 x 2 x 2 box: per-pixel transmittance (reference (a));
//  - spacing 1e-6 and 1e6, origin at 1e7, with the camera and lights scaled / moved along
//    and density_scale divided by the scale: the same image as at unit spacing and origin 0
//    within noise (independent seeds; per-pixel chi-square, Bonferroni, mean within 3 sigma);
//  - camera inside the volume, on a face, looking exactly along an axis (into, out of and
//    along the face); fov 1e-4 and 179.9 degrees; lens aperture 5x the volume: per-pixel
//    transmittance;
//  - lights inside an absorbing volume: per-pixel radiance
//      L = L_bg T(0, exit) + sum over lights met (front side) of Le T(0, t_light),
//    with the exact per-pixel sample variance from the second moment.
// All statistical checks at alpha = 1e-4.
#include <catch2/catch.hpp>

#include "accuracy_support.h"

using namespace tessera_acc;

namespace {

tessera::SceneDesc absorbing(double sigma, const tessera::CameraDesc& cam, int spp = 256) {
  tessera::SceneDesc s = unit_box_scene(sigma, 0.0);
  s.geometry.spacing = Vec3(0.5);  // the 3^3 UnitBox field; other fields set their own
  s.background.color = Color(1.0);
  s.camera = cam;
  s.image = {16, 16, spp, 0.0};
  s.options.seed = 1000;
  return s;
}

tessera::CameraDesc camera(const Vec3& pos, const Vec3& at, const Vec3& up, double fov) {
  tessera::CameraDesc c;
  c.position = pos;
  c.look_at = at;
  c.up = up;
  c.fov_deg = fov;
  return c;
}

/// The unit box as a 3^3 constant field.
struct UnitBox {
  std::vector<float> f = constant_field(3, 3, 3, 1.0f);
  FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, 3, 3, 3);
};

void expect_box(const tessera::SceneDesc& s, const FieldView& view, const Vec3& lo, const Vec3& hi,
                const std::string& what, int m = 64) {
  tessera::RenderStats st;
  const PixelTest t = absorbing_box_test(view, s, lo, hi, s.tf.density_scale, m, &st);
  INFO(what << ": " << t.describe());
  CHECK(t.ok());
  CHECK(t.mean_z() < 4.0);
  CHECK(st.discarded_samples == 0);
}

}  // namespace

TEST_CASE("one or two vertices along an axis", "[accuracy][stress]") {
  const tessera::CameraDesc cam = camera(Vec3(1.8, 1.5, -1.4), Vec3(0.5, 0.5, 0.5), Vec3(0, 1, 0), 40.0);
  SECTION("one vertex along x: no thickness, the background exactly") {
    const std::vector<float> f = constant_field(1, 4, 4, 1.0f);
    const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, 1, 4, 4);
    tessera::SceneDesc s = absorbing(3.0, cam, 16);
    s.geometry.spacing = Vec3(1.0, 1.0 / 3.0, 1.0 / 3.0);
    tessera::RenderStats st;
    const tessera::Film film = render(view, s, &st);
    bool all_background = true;
    for (const tessera::PixelSums& p : film.pixels())
      all_background = all_background && p.r == static_cast<double>(p.n);
    CHECK(all_background);
    CHECK(st.free_flight_lookups == 0);
  }
  SECTION("a single vertex") {
    const float v = 1.0f;
    const FieldView view = FieldView::contiguous(&v, tessera::DType::Float32, 1, 1, 1);
    tessera::RenderStats st;
    const tessera::Film film = render(view, absorbing(3.0, cam, 4), &st);
    CHECK(all_finite(film));
    CHECK(st.free_flight_lookups == 0);
  }
  SECTION("two vertices along z: a one-voxel slab") {
    const std::vector<float> f = constant_field(4, 4, 2, 1.0f);
    const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, 4, 4, 2);
    tessera::SceneDesc s = absorbing(4.0, cam);
    s.geometry.spacing = Vec3(1.0 / 3.0, 1.0 / 3.0, 0.3);
    expect_box(s, view, Vec3(0.0), Vec3(1.0, 1.0, 0.3), "slab");
  }
  SECTION("2 x 2 x 2 vertices") {
    const std::vector<float> f = constant_field(2, 2, 2, 1.0f);
    const FieldView view = FieldView::contiguous(f.data(), tessera::DType::Float32, 2, 2, 2);
    tessera::SceneDesc s = absorbing(2.0, cam);
    s.geometry.spacing = Vec3(1.0);
    expect_box(s, view, Vec3(0.0), Vec3(1.0), "2^3");
  }
}

TEST_CASE("spacing 1e-6 and 1e6, origin 1e7: the unit image within noise", "[accuracy][stress]") {
  constexpr int kN = 13;
  const std::vector<float> field = cloud_field(kN, kN, kN);
  const FieldView view = FieldView::contiguous(field.data(), tessera::DType::Float32, kN, kN, kN);
  // A lit, scattering, emitting cloud; everything with a length is placed by `place`.
  auto scene = [&](double scale, const Vec3& offset, std::uint64_t seed) {
    auto place = [&](const Vec3& p) { return offset + scale * p; };
    tessera::SceneDesc s = unit_box_scene(20.0 / scale, 0.85);
    s.geometry.origin = offset;
    s.geometry.spacing = Vec3(scale / (kN - 1));
    s.tf.opacity = tessera::ScalarTF({0.0, 0.1, 1.0}, {0.0, 0.3, 1.0});
    s.tf.specular = tessera::ColorTF::constant(Color(0.04));
    s.integrator.shading = tessera::Shading::Hybrid;
    s.integrator.scattering = tessera::Scattering::Multiple;
    s.integrator.max_bounces = 6;
    s.camera = camera(place(Vec3(1.5, 1.1, -1.6)), place(Vec3(0.5, 0.5, 0.5)), Vec3(0, 1, 0), 35.0);
    s.lights.push_back(tessera::RectLightDesc{place(Vec3(0.5, 1.8, 0.5)), place(Vec3(0.5, 0.0, 0.5)), 0.8 * scale,
                                              0.8 * scale, Color(4.0)});
    s.lights.push_back(tessera::SphereLightDesc{place(Vec3(-0.8, 0.4, 0.3)), 0.25 * scale, Color(3.0)});
    s.background.color = Color(0.2);
    s.image = {16, 16, 64, 0.0};
    s.options.seed = seed;
    return s;
  };
  const tessera::Film unit = render(view, scene(1.0, Vec3(0.0), 1100));
  struct Case {
    const char* name;
    double scale;
    Vec3 offset;
  };
  const Case cases[] = {{"spacing 1e-6", 1e-6, Vec3(0.0)},
                        {"spacing 1e6", 1e6, Vec3(0.0)},
                        {"origin 1e7", 1.0, Vec3(1e7, -1e7, 1e7)},
                        {"spacing 1e-3 at origin 1e7", 1e-3, Vec3(1e7, 1e7, -1e7)}};
  std::uint64_t seed = 1101;
  for (const Case& c : cases) {
    tessera::RenderStats st;
    const tessera::Film f = render(view, scene(c.scale, c.offset, seed++), &st);
    const PixelTest t = compare_films(f, unit);
    INFO(c.name << ": " << t.describe());
    CHECK(all_finite(f));
    CHECK(st.discarded_samples == 0);
    CHECK(t.ok());
    CHECK(std::fabs(t.mean_diff) < 3.0 * t.mean_diff_se);
  }
}

TEST_CASE("camera inside, on a face, along an axis, fov extremes, huge aperture", "[accuracy][stress]") {
  const UnitBox box;
  const Vec3 lo(0.0), hi(1.0);
  SECTION("inside the volume, looking exactly along +z") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.4, 0.55, 0.45), Vec3(0.4, 0.55, 3.0), Vec3(0, 1, 0), 70.0));
    expect_box(s, box.view, lo, hi, "inside");
  }
  SECTION("inside the volume, thin lens looking exactly along -x") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.7, 0.5, 0.5), Vec3(-2.0, 0.5, 0.5), Vec3(0, 0, 1), 60.0));
    s.camera.aperture = 0.2;
    expect_box(s, box.view, lo, hi, "inside, thin lens");
  }
  SECTION("on the face z = 0, looking into the volume along +z") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.5, 0.5, 0.0), Vec3(0.5, 0.5, 1.0), Vec3(0, 1, 0), 60.0));
    expect_box(s, box.view, lo, hi, "face, inward");
  }
  SECTION("on the face z = 0, looking out along -z: the background exactly") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.5, 0.5, 0.0), Vec3(0.5, 0.5, -1.0), Vec3(0, 1, 0), 60.0));
    tessera::RenderStats st;
    const tessera::Film film = render(box.view, s, &st);
    bool all_background = true;
    for (const tessera::PixelSums& p : film.pixels())
      all_background = all_background && p.r == static_cast<double>(p.n);
    CHECK(all_background);
    CHECK(st.real_collisions == 0);
  }
  SECTION("on the face z = 0, looking along it (+y): half the rays graze into the box") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.5, 0.2, 0.0), Vec3(0.5, 2.0, 0.0), Vec3(0, 0, 1), 60.0));
    expect_box(s, box.view, lo, hi, "face, along the face");
  }
  SECTION("on an edge (x = 0, z = 0), looking along the edge") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.0, -0.5, 0.0), Vec3(0.0, 2.0, 0.0), Vec3(0, 0, 1), 50.0));
    expect_box(s, box.view, lo, hi, "edge");
  }
  SECTION("fov 1e-4 degrees") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(2.0, 1.6, -1.5), Vec3(0.45, 0.5, 0.55), Vec3(0, 1, 0), 1e-4));
    expect_box(s, box.view, lo, hi, "fov 1e-4", 8);
  }
  SECTION("fov 179.9 degrees, from inside (the volume fills the view)") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(0.45, 0.5, 0.3), Vec3(0.45, 0.5, 0.5), Vec3(0, 1, 0), 179.9));
    expect_box(s, box.view, lo, hi, "fov 179.9", 128);
  }
  SECTION("aperture 5x the volume") {
    tessera::SceneDesc s = absorbing(1.5, camera(Vec3(2.5, 1.8, -2.2), Vec3(0.5, 0.5, 0.5), Vec3(0, 1, 0), 40.0));
    s.camera.aperture = 5.0;
    expect_box(s, box.view, lo, hi, "aperture 5");
  }
}

TEST_CASE("lights inside an absorbing volume: Le T(0, t_light) + L_bg T(0, exit) per pixel", "[accuracy][stress]") {
  const UnitBox box;
  const double sigma = 1.2;
  tessera::SceneDesc s = absorbing(sigma, camera(Vec3(1.9, 1.3, -1.6), Vec3(0.5, 0.5, 0.5), Vec3(0, 1, 0), 38.0), 512);
  s.background.color = Color(0.5);
  const tessera::SphereLightDesc sph{Vec3(0.35, 0.55, 0.5), 0.2, Color(3.0)};
  const tessera::RectLightDesc rect{Vec3(0.7, 0.4, 0.6), Vec3(1.7, 0.9, -0.6), 0.35, 0.25, Color(2.0)};
  s.lights.push_back(sph);
  s.lights.push_back(rect);
  // Reference intersections written from docs/physics.md section 7.
  const Vec3 rn = glm::normalize(rect.target - rect.position);
  const Vec3 ref = std::fabs(rn.z) > 0.999 ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
  const Vec3 ru = glm::normalize(glm::cross(ref, rn)), rv = glm::cross(rn, ru);
  // A sample is X = sum over emitters i met (lights, then the background at t = inf) of
  // c_i 1[no collision before t_i], so E[X | ray] = sum c_i T(t_i) and
  // E[X^2 | ray] = sum_ij c_i c_j T(max(t_i, t_j)): exact pixel means and sample variances.
  auto moment = [&](const Ray& r, int order) {
    double t0, t1;
    const bool in = box_interval(r, Vec3(0.0), Vec3(1.0), &t0, &t1);
    auto T = [&](double t) { return in ? std::exp(-sigma * std::max(0.0, std::min(t, t1) - t0)) : 1.0; };
    double ts[3], cs[3];
    int n = 0;
    ts[n] = INFINITY, cs[n++] = 0.5;
    // Sphere: front (outside-facing) hit from outside.
    const Vec3 oc = r.o - sph.center;
    const double b = glm::dot(oc, r.d), c = glm::dot(oc, oc) - sph.radius * sph.radius;
    if (c > 0.0 && b < 0.0 && b * b - c >= 0.0) ts[n] = -b - std::sqrt(b * b - c), cs[n++] = 3.0;
    // Rect: one-sided, the ray must travel against its normal.
    const double dn = glm::dot(r.d, rn);
    if (dn < 0.0) {
      const double t = glm::dot(rect.position - r.o, rn) / dn;
      const Vec3 p = r.o + t * r.d - rect.position;
      if (t > 0.0 && std::fabs(glm::dot(p, ru)) <= 0.5 * rect.width && std::fabs(glm::dot(p, rv)) <= 0.5 * rect.height)
        ts[n] = t, cs[n++] = 2.0;
    }
    double m = 0.0;
    for (int i = 0; i < n; ++i) {
      if (order == 1) m += cs[i] * T(ts[i]);
      else
        for (int j = 0; j < n; ++j) m += cs[i] * cs[j] * T(std::max(ts[i], ts[j]));
    }
    return m;
  };
  const std::vector<double> expected = expected_image(s, 48, [&](const Ray& r) { return moment(r, 1); });
  const std::vector<double> second = expected_image(s, 48, [&](const Ray& r) { return moment(r, 2); });
  std::vector<double> var(expected.size());
  for (std::size_t i = 0; i < var.size(); ++i) var[i] = std::max(0.0, second[i] - expected[i] * expected[i]);
  tessera::RenderStats st;
  const tessera::Film film = render(box.view, s, &st);
  const PixelTest t = compare_to_expected(film, expected, &var);
  INFO(t.describe());
  CHECK(all_finite(film));
  CHECK(t.ok());
  CHECK(t.mean_z() < 4.0);
  // The same lights inside a scattering cloud: finite and nothing discarded.
  s.tf.diffuse = tessera::ColorTF::constant(Color(0.9));
  s.integrator.scattering = tessera::Scattering::Multiple;
  s.image.spp = 32;
  const tessera::Film scat = render(box.view, s, &st);
  CHECK(all_finite(scat));
  CHECK(st.discarded_samples == 0);
}
