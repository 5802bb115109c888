#!/usr/bin/env python3
"""Bytes moved per render and field memory per rank, on paper: replicated mode, Tessera's
demand-paged distributed mode, and ray forwarding (Galaxy-style), for 64 and 1024 nodes
(docs/mpi.md, "Distributed mode"; docs/BENCHMARKS.md). Prints a table and writes CSV.

    python3 bench/traffic_model.py [--csv FILE] [--touched F] [--refetch R]

Assumptions (one rank per node; field of N^3 float32 vertices, F bytes):
- replicated: every node receives the part of the field it does not own, F (1 - 1/P), each
  render; memory per node F.
- paged: a rank fetches the bricks its rays touch outside its own block. `touched` is the
  fraction of the field's non-empty bricks a rank's rays touch (1 for a dense haze seen from
  outside with shadows and scattering: every ray crosses the whole volume; ~0.1-0.3 for sparse
  features), `refetch` how often a brick is fetched again after a flush (1 when the working
  set fits the cache). Bytes = P * touched * F (1 - 1/P) * refetch. Memory per rank: its
  block F / P plus the cache, at most 0.4 F.
- ray forwarding: each path segment (camera ray; per real collision a shadow ray and a
  scattered ray) crosses about P^(1/3) / 2 block faces on average (segments span about half
  the domain); each crossing moves the ray's state (96 bytes: origin, direction, throughput,
  pixel and sample ids, RNG counter, depth, t_max); each sample returns one contribution to
  its pixel's owner (32 bytes). Segments per sample: 1 + 2 L, L the mean real collisions per
  path (single scattering: L <= 1; multiple: L ~ 3). Memory per rank: its block F / P plus
  ray queues.
"""
import argparse
import csv


def model(N, P, W, H, spp, L, touched, refetch):
    F = 4.0 * N ** 3
    samples = W * H * spp
    segments = samples * (1 + 2 * L)
    crossings = max(0.0, P ** (1.0 / 3.0) / 2.0)
    return {
        "replicated_bytes": P * F * (1 - 1.0 / P),
        "replicated_mem_per_rank": F,
        "paged_bytes": P * touched * F * (1 - 1.0 / P) * refetch,
        "paged_mem_per_rank": F / P + min(0.4 * F, touched * F),
        "forward_bytes": segments * crossings * 96 + samples * 32,
        "forward_mem_per_rank": F / P,
    }


def human(b):
    for unit in ["B", "KB", "MB", "GB", "TB", "PB"]:
        if b < 1000:
            return f"{b:.3g} {unit}"
        b /= 1000.0
    return f"{b:.3g} EB"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", default="bench/results/traffic_model.csv")
    ap.add_argument("--touched", type=float, default=1.0)
    ap.add_argument("--refetch", type=float, default=1.0)
    a = ap.parse_args()
    rows = []
    print(f"{'N':>5} {'P':>5} {'image':>9} {'spp':>4} {'L':>2} | {'replicated':>10} | "
          f"{'paged':>10} | {'forwarding':>10} | mem/rank repl / paged / fwd")
    for N in (2048, 4096):
        for P in (64, 1024):
            for (W, H, spp) in ((1024, 1024, 16), (1024, 1024, 256)):
                for L in (1, 3):
                    m = model(N, P, W, H, spp, L, a.touched, a.refetch)
                    rows.append({"N": N, "P": P, "image": f"{W}x{H}", "spp": spp, "L": L,
                                 "touched": a.touched, "refetch": a.refetch, **m})
                    print(f"{N:>5} {P:>5} {W}x{H} {spp:>4} {L:>2} | {human(m['replicated_bytes']):>10} | "
                          f"{human(m['paged_bytes']):>10} | {human(m['forward_bytes']):>10} | "
                          f"{human(m['replicated_mem_per_rank'])} / {human(m['paged_mem_per_rank'])} / "
                          f"{human(m['forward_mem_per_rank'])}")
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {a.csv}")


if __name__ == "__main__":
    main()
