#!/usr/bin/env python3
"""Compares a tessera-heat --device cuda run with a CPU run (heat_gpu_runs.cmake).

    compare_heat_runs.py CPU_DIR GPU_DIR

field.raw (--dump, float32): the same size, every value finite, and equal to float32 rounding
(the device field equals the CPU's within 1e-12 relative: tests/miniapp_gpu/test_heat_solver_cuda.cpp;
a value next to a float32 rounding boundary may round to the neighbouring float).
heat_far_000010.png, heat_close_000010.png: the same size, and the mean absolute difference
per channel within Monte Carlo error: with the same seeds and samples per pixel the GPU's paths
follow the CPU's almost everywhere (docs/gpu.md), so the 8-bit images differ by far less than
4 levels on average; a wrong field, camera or transfer function differs by tens.
Only the standard library (PNGs read by tests/common/png_decode.py). Prints one line per check;
exits 1 on a failure.
"""
import array
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from png_decode import read_png  # noqa: E402


def main():
    cpu_dir, gpu_dir = sys.argv[1], sys.argv[2]
    failures = 0
    fields = []
    for d in (cpu_dir, gpu_dir):
        a = array.array("f")
        a.frombytes(open(os.path.join(d, "field.raw"), "rb").read())
        fields.append(a)
    cpu, gpu = fields
    if len(cpu) != len(gpu) or not cpu:
        print(f"field.raw: {len(gpu)} values on the GPU, {len(cpu)} on the CPU")
        return 1
    if not all(math.isfinite(v) for v in gpu):
        print("field.raw: the GPU's field has non-finite values")
        failures += 1
    worst = max(abs(g - c) / max(abs(c), 1.0) for c, g in zip(cpu, gpu))
    print(f"field.raw: {len(cpu)} values, largest relative difference {worst:.3g} (allowed 1e-6)")
    if not worst <= 1e-6:
        failures += 1
    for name in ("heat_far_000010.png", "heat_close_000010.png"):
        wc, hc, cc, rows_c = read_png(os.path.join(cpu_dir, name))
        wg, hg, cg, rows_g = read_png(os.path.join(gpu_dir, name))
        pc, pg = b"".join(rows_c), b"".join(rows_g)
        if (wc, hc, cc) != (wg, hg, cg):
            print(f"{name}: {wg}x{hg}x{cg} on the GPU, {wc}x{hc}x{cc} on the CPU")
            failures += 1
            continue
        mean = sum(abs(a - b) for a, b in zip(pc, pg)) / len(pc)
        print(f"{name}: mean absolute difference {mean:.3f} levels of 255 (allowed 4)")
        if not mean <= 4.0:
            failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
