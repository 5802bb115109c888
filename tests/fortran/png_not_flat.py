#!/usr/bin/env python3
"""png_not_flat.py A.png [B.png ...]: exits 1 unless every PNG is a picture, not a flat image:
the standard deviation of its luminance (0..255) is at least 2 and at least 1% of its pixels
differ from the median by more than 8 (a render that drew nothing is one background gradient
whose sd stays small). Prints the figures."""
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from png_decode import read_png  # noqa: E402


def main(paths):
    failed = 0
    for path in paths:
        width, height, bpp, rows = read_png(path)
        y = [0.2126 * r[bpp * x] + 0.7152 * r[bpp * x + 1] + 0.0722 * r[bpp * x + 2] for r in rows for x in range(width)]
        sd, median = statistics.pstdev(y), statistics.median(y)
        share = sum(abs(v - median) > 8 for v in y) / len(y)
        flat = sd < 2 or share < 0.01
        print(f"{path}: luminance sd {sd:.1f}, {100 * share:.1f}% of pixels off the median: "
              f"{'FLAT' if flat else 'a picture'}")
        failed += flat
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
