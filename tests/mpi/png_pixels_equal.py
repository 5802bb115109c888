"""png_pixels_equal.py A.png B.png: exit 0 when the two PNGs (8-bit, non-interlaced, RGB or
RGBA) have the same size and pixels, decoded with the standard library alone
(tests/common/png_decode.py), so that another zlib or filter choice does not matter; else 1
with a reason."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from png_decode import read_png  # noqa: E402


def pixels(path):
    width, height, bpp, rows = read_png(path)
    return (width, height, bpp), b"".join(rows)


(shape_a, a), (shape_b, b) = pixels(sys.argv[1]), pixels(sys.argv[2])
if shape_a != shape_b:
    sys.exit(f"{sys.argv[1]} is {shape_a}, {sys.argv[2]} is {shape_b}")
if a != b:
    differ = sum(1 for x, y in zip(a, b) if x != y)
    sys.exit(f"{sys.argv[1]} and {sys.argv[2]}: {differ} of {len(a)} bytes of pixels differ")
