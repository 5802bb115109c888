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
Only the standard library (zlib for the PNGs). Prints one line per check; exits 1 on a failure.
"""
import array
import math
import os
import struct
import sys
import zlib


def read_png(path):
    """(width, height, channels, bytes) of an 8-bit, non-interlaced grey/RGB/RGBA PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    width, height, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace:
        raise ValueError(f"{path}: PNG depth {depth}, colour type {colour}, interlace {interlace} not read here")
    raw, stride = zlib.decompress(idat), width * channels
    out, prev = bytearray(), bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b, c = prev[x], prev[x - channels] if x >= channels else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return width, height, channels, bytes(out)


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
        wc, hc, cc, pc = read_png(os.path.join(cpu_dir, name))
        wg, hg, cg, pg = read_png(os.path.join(gpu_dir, name))
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
