#pragma once
/// The geometry of one element from its vertex positions (VTK's vertex order): the tet's
/// barycentric coordinates, the hex's trilinear map, its Jacobian and its inverse by Newton's
/// method (physics.md section 10). Pure functions of the corners: no allocation, no virtual
/// call, the same arithmetic in the same order whatever domain or position the element has.
/// Host and device code (host_device.h).
#include <tessera/host_device.h>
#include <tessera/math.h>

#include <algorithm>
#include <cmath>

namespace tessera {

/// Parametric corner of a hex's vertex v (VTK order): r, s, t in {0, 1}. Device code reads its
/// own copies of the tables (host_device.h, TESSERA_TABLE).
inline constexpr int kHexCornerR[8] = {0, 1, 1, 0, 0, 1, 1, 0};
inline constexpr int kHexCornerS[8] = {0, 0, 1, 1, 0, 0, 1, 1};
inline constexpr int kHexCornerT[8] = {0, 0, 0, 0, 1, 1, 1, 1};
TESSERA_DEVICE_TABLE(kHexCornerR);
TESSERA_DEVICE_TABLE(kHexCornerS);
TESSERA_DEVICE_TABLE(kHexCornerT);

/// Newton's method on the trilinear map: the update that counts as converged (parametric,
/// i.e. relative to the cell's size), and the most iterations tried.
inline constexpr double kNewtonTolerance = 1e-10;
inline constexpr int kNewtonMaxIterations = 24;
/// Parametric (or barycentric) slack within which a point still lies in an element, so that
/// a point on a shared face, rounded either way, is found in one of its two elements.
inline constexpr double kInsideSlack = 1e-9;

/// det[a b c] (columns).
TESSERA_HOST_DEVICE inline double det3(const Vec3& a, const Vec3& b, const Vec3& c) {
  return glm::dot(a, glm::cross(b, c));
}

/// Six times the signed volume of tet (p0, p1, p2, p3): positive in VTK's orientation.
TESSERA_HOST_DEVICE inline double tet_volume6(const Vec3* c) { return det3(c[1] - c[0], c[2] - c[0], c[3] - c[0]); }

/// Barycentric weights w[0..3] of x in tet c (Cramer's rule); false for a flat tet.
TESSERA_HOST_DEVICE inline bool tet_barycentric(const Vec3* c, const Vec3& x, double w[4]) {
  const Vec3 e1 = c[1] - c[0], e2 = c[2] - c[0], e3 = c[3] - c[0], d = x - c[0];
  const double det = det3(e1, e2, e3);
  if (!(det != 0.0)) return false;
  const double inv = 1.0 / det;
  w[1] = det3(d, e2, e3) * inv;
  w[2] = det3(e1, d, e3) * inv;
  w[3] = det3(e1, e2, d) * inv;
  w[0] = 1.0 - w[1] - w[2] - w[3];
  return true;
}

/// The hex's trilinear shape functions at parametric r (VTK order).
TESSERA_HOST_DEVICE inline void hex_weights(const double r[3], double w[8]) {
  const double a[2] = {1.0 - r[0], r[0]}, b[2] = {1.0 - r[1], r[1]}, c[2] = {1.0 - r[2], r[2]};
  for (int v = 0; v < 8; ++v)
    w[v] = a[TESSERA_TABLE(kHexCornerR)[v]] * b[TESSERA_TABLE(kHexCornerS)[v]] * c[TESSERA_TABLE(kHexCornerT)[v]];
}

/// x(r) of the hex's trilinear map.
TESSERA_HOST_DEVICE inline Vec3 hex_map(const Vec3* c, const double r[3]) {
  double w[8];
  hex_weights(r, w);
  Vec3 x(0.0);
  for (int v = 0; v < 8; ++v) x += w[v] * c[v];
  return x;
}

/// The Jacobian's columns dx/dr, dx/ds, dx/dt at parametric r.
TESSERA_HOST_DEVICE inline void hex_jacobian(const Vec3* c, const double r[3], Vec3 J[3]) {
  const double a[2] = {1.0 - r[0], r[0]}, b[2] = {1.0 - r[1], r[1]}, t[2] = {1.0 - r[2], r[2]};
  J[0] = J[1] = J[2] = Vec3(0.0);
  for (int v = 0; v < 8; ++v) {
    const int i = TESSERA_TABLE(kHexCornerR)[v], j = TESSERA_TABLE(kHexCornerS)[v], k = TESSERA_TABLE(kHexCornerT)[v];
    const double si = i ? 1.0 : -1.0, sj = j ? 1.0 : -1.0, sk = k ? 1.0 : -1.0;
    J[0] += (si * b[j] * t[k]) * c[v];
    J[1] += (a[i] * sj * t[k]) * c[v];
    J[2] += (a[i] * b[j] * sk) * c[v];
  }
}

/// The vertex at parametric corner (i, j, k), each 0 or 1: the inverse of kHexCornerR/S/T.
TESSERA_HOST_DEVICE inline int hex_vertex_at(int i, int j, int k) { return 4 * k + (j ? 3 - i : i); }

/// det J at the parametric corner of vertex v. There the weights of hex_jacobian are 0 or 1:
/// each column is the difference of the two vertices on the corner's edge along that axis,
/// which is what hex_jacobian sums to (the other six terms add zeros), at an eighth of its cost.
TESSERA_HOST_DEVICE inline double hex_corner_jacobian(const Vec3* c, int v) {
  const int i = TESSERA_TABLE(kHexCornerR)[v], j = TESSERA_TABLE(kHexCornerS)[v], k = TESSERA_TABLE(kHexCornerT)[v];
  return det3(c[hex_vertex_at(1, j, k)] - c[hex_vertex_at(0, j, k)],
              c[hex_vertex_at(i, 1, k)] - c[hex_vertex_at(i, 0, k)],
              c[hex_vertex_at(i, j, 1)] - c[hex_vertex_at(i, j, 0)]);
}

/// Parametric r of world point x in hex c by Newton's method from the centre: true once an
/// update is below kNewtonTolerance (r then holds the converged point, inside or not), false
/// when the Jacobian is singular or kNewtonMaxIterations pass (r unusable).
TESSERA_HOST_DEVICE inline bool hex_inverse(const Vec3* c, const Vec3& x, double r[3]) {
  r[0] = r[1] = r[2] = 0.5;
  for (int it = 0; it < kNewtonMaxIterations; ++it) {
    Vec3 J[3];
    hex_jacobian(c, r, J);
    const double det = det3(J[0], J[1], J[2]);
    if (!(det != 0.0) || !std::isfinite(det)) return false;
    const Vec3 f = hex_map(c, r) - x;
    const double inv = 1.0 / det;
    const double d[3] = {det3(f, J[1], J[2]) * inv, det3(J[0], f, J[2]) * inv, det3(J[0], J[1], f) * inv};
    r[0] -= d[0];
    r[1] -= d[1];
    r[2] -= d[2];
    const double step = std::max(std::max(std::fabs(d[0]), std::fabs(d[1])), std::fabs(d[2]));
    if (!(step < 4.0)) return false;  // diverging: x is far outside the element
    if (step < kNewtonTolerance) return true;
  }
  return false;
}

/// True when every parametric coordinate lies in [-kInsideSlack, 1 + kInsideSlack].
TESSERA_HOST_DEVICE inline bool inside_unit(const double r[3]) {
  for (int a = 0; a < 3; ++a)
    if (!(r[a] >= -kInsideSlack && r[a] <= 1.0 + kInsideSlack)) return false;
  return true;
}

}  // namespace tessera
