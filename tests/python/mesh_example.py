"""Curvilinear and unstructured meshes from Python (docs/python.md, "Curvilinear and
unstructured meshes"; the C and Fortran twins are tests/fortran/mesh_example.c and .f90): a
cylindrical shell, its vertex coordinates one (n, 3) array as finite-element codes hold them,
published as a curvilinear grid and, cut into tetrahedra, as an unstructured mesh, each
rendered with `renders: [{field: f}]`. Run by tests/python/test_meshes.py; on its own:
python mesh_example.py OUT_DIR."""
import sys

import numpy as np

import tessera

NI, NJ, NK = 9, 33, 9  # vertices along the radius, the angle (270 degrees) and the height
# Each hex cut into 6 tetrahedra around its diagonal 0-6 (VTK's vertex numbers), positively oriented
KUHN = np.array([[0, 1, 2, 6], [0, 3, 7, 6], [0, 4, 5, 6], [0, 5, 1, 6], [0, 2, 3, 6], [0, 7, 4, 6]])


def shell():
    """(xyz (n, 3), f (n,), hexes (ncells, 8)): vertex v = i + NI * (j + NJ * k), i fastest."""
    k, j, i = np.meshgrid(np.arange(NK), np.arange(NJ), np.arange(NI), indexing="ij")  # C order: i fastest
    r, theta, h = 1.0 + i / (NI - 1.0), 1.5 * np.pi * j / (NJ - 1.0), 1.5 * k / (NK - 1.0)
    xyz = np.stack([r * np.cos(theta), r * np.sin(theta), h], axis=-1).reshape(-1, 3)
    f = (np.exp(-4.0 * (r - 1.5) * (r - 1.5)) * (0.6 + 0.4 * np.sin(3.0 * theta)) * (0.5 + h / 3.0)).ravel()
    v = np.arange(NI * NJ * NK).reshape(NK, NJ, NI)
    corners = [v[:-1, :-1, :-1], v[:-1, :-1, 1:], v[:-1, 1:, 1:], v[:-1, 1:, :-1],  # VTK's hex order
               v[1:, :-1, :-1], v[1:, :-1, 1:], v[1:, 1:, 1:], v[1:, 1:, :-1]]
    hexes = np.stack([c.ravel() for c in corners], axis=-1).astype(np.int64)
    return xyz, f, hexes


def main(out_dir="out"):
    """Renders the shell (curvilinear) and its tetrahedra; returns {'shell': image, 'tets': image}."""
    xyz, f, hexes = shell()
    tets = hexes[:, KUHN].reshape(-1, 4).astype(np.int32)
    images = {}
    for name, domain in (("shell", {"coords": xyz, "dims": (NI, NJ, NK), "fields": {"f": f}}),
                         ("tets", {"coords": xyz, "shape": "tet", "connectivity": tets, "fields": {"f": f}})):
        with tessera.Adapter({"renders": [{"field": "f"}]}, output_dir=f"{out_dir}/{name}", quiet=True) as viz:
            images[name] = viz.execute_mesh_domains(0, 0.0, [domain])["f"]
            assert viz.last_status == 0, viz.last_error
    return images


if __name__ == "__main__":
    print({name: image.shape for name, image in main(*sys.argv[1:]).items()})
