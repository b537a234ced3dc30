#!/usr/bin/env python3
"""Generates the demo collider meshes (OBJ) in this folder: sphere, funnel, pea shooter, crate,
tank, terrain.

Standard library only. The .obj files it writes are committed, so nothing is generated at build
time; run it again only to change a shape: `python3 assets/make_meshes.py`.

Units are metres, +y is up. Every mesh is closed, welded (shared vertices), consistently oriented
with outward counter-clockwise triangles, and free of self-intersections; the script checks the
first three and fails loudly otherwise.
"""

import math
import os
import sys
from collections import Counter

HERE = os.path.dirname(os.path.abspath(__file__))
MAX_TRIANGLES = 5000


def icosphere(radius, subdivisions):
    """Icosahedron subdivided `subdivisions` times, vertices projected onto the sphere."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [normalize(v) for v in verts]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
            (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
            (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                verts.append(normalize(add(verts[a], verts[b])))
                midpoints[key] = len(verts) - 1
            return midpoints[key]

        refined = []
        for a, b, c in tris:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = refined
    return [scale(v, radius) for v in verts], tris


def revolve(profile, segments):
    """Solid of revolution around the y axis of a closed (r, y) polygon with every r > 0.

    The result is a closed ring-shaped solid (genus 1): a tube, a funnel. Quads between
    neighbouring meridians are split into two triangles; orientation is fixed afterwards.
    """
    n = len(profile)
    verts = []
    for s in range(segments):
        angle = 2.0 * math.pi * s / segments
        for r, y in profile:
            verts.append((r * math.cos(angle), y, r * math.sin(angle)))

    def at(s, p):
        return (s % segments) * n + (p % n)

    tris = []
    for s in range(segments):
        for p in range(n):
            a, b, c, d = at(s, p), at(s + 1, p), at(s + 1, p + 1), at(s, p + 1)
            tris += [(a, b, c), (a, c, d)]
    return orient_outward(verts, tris)


def open_box(width, height, depth, wall, floor):
    """A tank: an axis-aligned box open at the top (+y) with walls `wall` and floor `floor`
    thick, as one closed solid (outside, rim, inner walls and inner floor)."""
    ax, az = width / 2.0, depth / 2.0
    ix, iz = ax - wall, az - wall
    verts = []

    def ring(hx, y, hz):  # four corners counter-clockwise seen from +y
        start = len(verts)
        verts.extend([(-hx, y, -hz), (-hx, y, hz), (hx, y, hz), (hx, y, -hz)])
        return list(range(start, start + 4))

    outer_bottom = ring(ax, 0.0, az)
    outer_top = ring(ax, height, az)
    inner_top = ring(ix, height, iz)
    inner_bottom = ring(ix, floor, iz)
    quads = []  # (quad, outward normal)
    quads.append((outer_bottom[::-1], (0, -1, 0)))
    quads.append((inner_bottom, (0, 1, 0)))
    for i in range(4):
        j = (i + 1) % 4
        mid = scale(add(verts[outer_bottom[i]], verts[outer_bottom[j]]), 0.5)
        side = normalize((mid[0], 0.0, mid[2]))
        axis_normal = tuple(float(round(c)) if abs(c) > 0.5 else 0.0 for c in side)
        quads.append(([outer_bottom[i], outer_bottom[j], outer_top[j], outer_top[i]], axis_normal))
        quads.append(([outer_top[i], outer_top[j], inner_top[j], inner_top[i]], (0, 1, 0)))
        quads.append(([inner_top[i], inner_top[j], inner_bottom[j], inner_bottom[i]],
                      scale(axis_normal, -1.0)))
    tris = []
    for quad, normal in quads:
        a, b, c, d = quad
        for tri in ((a, b, c), (a, c, d)):
            if dot(face_normal(verts, tri), normal) < 0:
                tri = (tri[0], tri[2], tri[1])
            tris.append(tri)
    return verts, tris


def box(width, height, depth):
    """A solid axis-aligned box centred on the origin, each face split into two triangles."""
    hx, hy, hz = width / 2.0, height / 2.0, depth / 2.0
    verts = [(x, y, z) for z in (-hz, hz) for y in (-hy, hy) for x in (-hx, hx)]
    # Corner i has x = bit 0, y = bit 1, z = bit 2; quads listed outward counter-clockwise.
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return orient_outward(verts, tris)


def terrain_height(x, z):
    """[m] Height of the terrain's surface: a big hill, two smaller ones, a hollow between them
    where water gathers, a winding gully from the big hill down to it, and a ripple so no two
    slopes are alike."""
    def bump(cx, cz, height, spread):
        return height * math.exp(-((x - cx) ** 2 + (z - cz) ** 2) / spread)
    # A gully from the big hill's flank down to the hollow: 12 cm deep along the diagonal.
    along = (x + z) / math.sqrt(2.0)
    across = (x - z) / math.sqrt(2.0) - 0.25 * math.sin(1.3 * along)
    taper = min(max((along + 2.2) / 0.6, 0.0), 1.0) * min(max((2.0 - along) / 0.6, 0.0), 1.0)
    gully = 0.12 * taper * math.exp(-across ** 2 / 0.04)
    h = (0.25 + bump(-1.8, -1.8, 0.9, 1.2) + bump(2.0, -1.5, 0.5, 0.8) + bump(-1.5, 2.0, 0.4, 0.8)
         - bump(1.2, 1.2, 0.2, 0.6) + 0.05 * math.sin(2.1 * x) * math.cos(1.7 * z) - gully)
    return max(h, 0.05)


def terrain(size, cells):
    """A height field over the square [-size/2, size/2]^2 (x, z) closed into a solid: the
    surface on top (`cells` x `cells` quads, each two triangles), vertical sides down to y = 0,
    and a floor fanned from its centre."""
    n = cells + 1
    step = size / cells
    coords = [-size / 2 + i * step for i in range(n)]
    verts = [(x, terrain_height(x, z), z) for z in coords for x in coords]
    tris = []
    for j in range(cells):
        for i in range(cells):
            a, b = j * n + i, j * n + i + 1
            c, d = (j + 1) * n + i, (j + 1) * n + i + 1
            tris += [(a, c, b), (b, c, d)] # counter-clockwise seen from +y
    # The boundary of the top, against the direction its triangles run along it, and a floor
    # vertex under each.
    ring = ([i for i in range(n)] + [j * n + cells for j in range(1, n)] +
            [cells * n + i for i in range(cells - 1, -1, -1)] +
            [j * n for j in range(cells - 1, 0, -1)])
    base = len(verts)
    verts += [(verts[k][0], 0.0, verts[k][2]) for k in ring]
    centre = len(verts)
    verts.append((0.0, 0.0, 0.0))
    m = len(ring)
    for k in range(m):
        top0, top1 = ring[k], ring[(k + 1) % m]
        bottom0, bottom1 = base + k, base + (k + 1) % m
        tris += [(top0, top1, bottom0), (top1, bottom1, bottom0)]
        tris.append((centre, bottom0, bottom1))
    return orient_outward(verts, tris)


def rotate_y_to_x(verts):
    """Turns a mesh built around the y axis to lie along +x (a proper rotation about z)."""
    return [(y, -x, z) for x, y, z in verts]


# ---- small vector helpers --------------------------------------------------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    length = math.sqrt(dot(a, a))
    return scale(a, 1.0 / length)


def face_normal(verts, tri):
    a, b, c = (verts[i] for i in tri)
    return cross(sub(b, a), sub(c, a))


def signed_volume(verts, tris):
    return sum(dot(verts[a], cross(verts[b], verts[c])) for a, b, c in tris) / 6.0


def orient_outward(verts, tris):
    """Flips every triangle if the (consistently oriented) mesh encloses a negative volume."""
    if signed_volume(verts, tris) < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return verts, tris


# ---- checks and output -----------------------------------------------------------------------

def check(name, verts, tris):
    """Closed and consistently oriented: every directed edge exactly once, its reverse too."""
    directed = Counter()
    for a, b, c in tris:
        for e in ((a, b), (b, c), (c, a)):
            directed[e] += 1
    for (a, b), count in directed.items():
        if count != 1 or directed.get((b, a), 0) != 1:
            sys.exit(f"make_meshes: {name}: edge {a}-{b} is not shared by exactly two "
                     f"oppositely oriented triangles")
    for tri in tris:
        if len(set(tri)) != 3 or dot(face_normal(verts, tri), face_normal(verts, tri)) == 0:
            sys.exit(f"make_meshes: {name}: degenerate triangle {tri}")
    volume = signed_volume(verts, tris)
    if volume <= 0:
        sys.exit(f"make_meshes: {name}: not oriented outward (volume {volume})")
    if len(tris) >= MAX_TRIANGLES:
        sys.exit(f"make_meshes: {name}: {len(tris)} triangles, over {MAX_TRIANGLES}")
    used = {i for tri in tris for i in tri}
    euler = len(used) - len(directed) // 2 + len(tris)
    return volume, 1 - euler // 2


def write_obj(name, comment, verts, tris):
    volume, genus = check(name, verts, tris)
    path = os.path.join(HERE, name + ".obj")
    with open(path, "w", newline="\n") as out:
        out.write(f"# {name}: {comment}\n")
        out.write("# Generated by assets/make_meshes.py; metres, +y up, outward CCW triangles.\n")
        out.write(f"# {len(verts)} vertices, {len(tris)} triangles, closed, genus {genus}\n")
        for x, y, z in verts:
            out.write(f"v {x:.9g} {y:.9g} {z:.9g}\n")
        for a, b, c in tris:
            out.write(f"f {a + 1} {b + 1} {c + 1}\n")
    print(f"{name}.obj: {len(verts)} vertices, {len(tris)} triangles, genus {genus}, "
          f"volume {volume:.6g} m^3")


def main():
    verts, tris = icosphere(0.25, 3)
    write_obj("sphere", "ball of radius 0.25 m at the origin (icosphere, 3 subdivisions)",
              verts, tris)

    # (r, y) profile, counter-clockwise: spout 0.03 m bore, 0.02 m walls, mouth 0.22 m radius.
    funnel = [(0.03, 0.0), (0.05, 0.0), (0.05, 0.18), (0.24, 0.5), (0.22, 0.5), (0.03, 0.18)]
    verts, tris = revolve(funnel, 48)
    write_obj("funnel", "funnel around +y, 0.5 m tall: 0.18 m spout, cone up to a 0.22 m mouth",
              verts, tris)

    # A blowpipe along +x: 0.03 m bore through 0.6 m, 0.02 m walls, a mouthpiece ring and a
    # muzzle lip.
    barrel = [(0.03, 0.0), (0.065, 0.0), (0.065, 0.05), (0.05, 0.065), (0.05, 0.54),
              (0.06, 0.58), (0.06, 0.6), (0.03, 0.6)]
    verts, tris = revolve(barrel, 48)
    verts = [(x - 0.3, y, z) for x, y, z in rotate_y_to_x(verts)]
    write_obj("peashooter", "pea shooter tube along +x from -0.3 to 0.3 m, 0.03 m bore, "
              "mouthpiece at -x", verts, tris)

    verts, tris = box(0.12, 0.12, 0.12)
    write_obj("crate", "solid cube 0.12 m on a side centred on the origin", verts, tris)

    verts, tris = open_box(0.8, 0.4, 0.5, 0.03, 0.03)
    write_obj("tank", "open-top tank 0.8 x 0.4 x 0.5 m (x, y up, z), 0.03 m walls and floor",
              verts, tris)

    verts, tris = terrain(6.0, 46)
    write_obj("terrain", "hills over 6 x 6 m (x, z), up to 1.2 m high, closed down to y = 0 "
              "(the level-scale scene's sparse collider)", verts, tris)


if __name__ == "__main__":
    main()
