#!/usr/bin/env python3
"""Device code calls no search or sort of the C++ standard library (docs/gpu.md, "One kernel
source for both"; ctest -L layout).

std::upper_bound compiled for the device (libstdc++ 12 under nvcc 13's --expt-relaxed-constexpr)
returned other indices than on the host on an H200, and sampled envmaps wrongly there. A file
that holds device code (TESSERA_HOST_DEVICE, __device__ or __global__, or a .cu/.cuh file) must
not call std::upper_bound, lower_bound, binary_search, equal_range, partition_point, sort,
stable_sort, partial_sort, nth_element or merge: write the loop out, as distribution.h does.
std::min, max and clamp are fine (checked on the device: tests/gpu/test_gpu_environment.cpp).

Usage: check_device_code.py REPO DIR...   (DIRs relative to REPO, searched recursively)
Prints each call as FILE:LINE and "N files checked, M calls" last; exit status 1 when M > 0.
"""
import os
import re
import sys

DEVICE = re.compile(r"\bTESSERA_HOST_DEVICE\b|__device__|__global__")
BANNED = re.compile(r"\bstd::(upper_bound|lower_bound|binary_search|equal_range|partition_point|sort|stable_sort|"
                    r"partial_sort|nth_element|merge|inplace_merge)\b")
SOURCES = (".h", ".hpp", ".cuh", ".cu", ".cpp")


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    repo = argv[1]
    files = calls = 0
    for d in argv[2:]:
        for root, _, names in os.walk(os.path.join(repo, d)):
            for name in sorted(names):
                if not name.endswith(SOURCES):
                    continue
                path = os.path.join(root, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                if not (name.endswith((".cu", ".cuh")) or DEVICE.search(text)):
                    continue
                files += 1
                for n, line in enumerate(text.splitlines(), 1):
                    code = line.split("//", 1)[0]
                    m = BANNED.search(code)
                    if m:
                        calls += 1
                        print(f"{os.path.relpath(path, repo)}:{n}: std::{m.group(1)} in a file with device code")
    print(f"{files} files checked, {calls} calls")
    return 1 if calls else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
