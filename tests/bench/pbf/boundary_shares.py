#!/usr/bin/env python3
"""How much of a particle's kernel a solid fills, exactly and as the closed form of phi gives it
(issue 25: "corners, edges and thin walls must come out right, not only flat faces").

The exact share is the poly6 kernel integrated over the solid by quadrature on a cube grid of
--cells per h; the closed form is the flat-boundary share B(phi / h) that pbf_lambda.comp uses
for bodies (the poly6 integral over a half-space at distance phi; docs/bodies.md). Shapes, with
the particle at distance d from each wall it faces (kernel radius h = 2 spacings):
  floor        the half-space y < 0;
  concave edge two walls meeting inside the fluid (y < 0 or x < 0), phi = d;
  corner       three walls (x < 0 or y < 0 or z < 0), phi = d;
  thin wall    a slab half a spacing thick (-s/2 < y < 0) with fluid on both sides, phi = d;
  convex edge  the fluid outside a solid's edge (y < 0 and x < 0), phi = sqrt(2) d;
and for the domain box, the corner product 1 - (1 - B(d))^k of the walls patch (docs/history.md,
"Boundary model", the walls patch of 2026-11-25).

    python3 tests/bench/pbf/boundary_shares.py [--cells 60]

Needs numpy.
"""

import argparse
import math

import numpy as np


def planar(u):
    """B(u): the poly6 kernel's share beyond a flat boundary at u = phi / h (deriveConstants)."""
    u = min(max(u, 0.0), 1.0)
    u2 = u * u
    return 0.5 - (315.0 / 256.0) * u * (
        1.0 + u2 * (-4.0 / 3.0 + u2 * (6.0 / 5.0 + u2 * (-4.0 / 7.0 + u2 / 9.0))))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cells", type=int, default=60, help="quadrature cells per h")
    a = p.parse_args()
    h, s = 1.0, 0.5
    n = 2 * a.cells
    c = (np.arange(n) + 0.5) / n * 2 * h - h
    x, y, z = np.meshgrid(c, c, c, indexing="ij")
    r2 = x * x + y * y + z * z
    w = np.where(r2 < h * h, (h * h - r2) ** 3, 0.0)
    w /= w.sum()

    def exact(solid, at):
        return float((w * solid(x + at[0], y + at[1], z + at[2])).sum())

    print("| d | floor exact / B(d) | concave edge exact / B(d) / product | corner exact / B(d) / "
          "product | thin wall (s/2) exact / B(d) | convex edge exact / B(sqrt2 d) |")
    print("|---|---|---|---|---|---|")
    for d in (0.5 * s, 1.0 * s, 1.5 * s):
        b = planar(d / h)
        floor = exact(lambda X, Y, Z: Y < 0, (0, d, 0))
        edge = exact(lambda X, Y, Z: (Y < 0) | (X < 0), (d, d, 0))
        corner = exact(lambda X, Y, Z: (Y < 0) | (X < 0) | (Z < 0), (d, d, d))
        thin = exact(lambda X, Y, Z: (Y < 0) & (Y > -0.5 * s), (0, d, 0))
        convex = exact(lambda X, Y, Z: (Y < 0) & (X < 0), (d, d, 0))
        print(f"| {d / s:.1f} s | {floor:.4f} / {b:.4f} | {edge:.4f} / {b:.4f} / "
              f"{1 - (1 - b) ** 2:.4f} | {corner:.4f} / {b:.4f} / {1 - (1 - b) ** 3:.4f} | "
              f"{thin:.4f} / {b:.4f} | {convex:.4f} / {planar(math.sqrt(2) * d / h):.4f} |")


if __name__ == "__main__":
    main()
