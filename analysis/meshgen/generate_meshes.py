#!/usr/bin/env python3
"""Writes nearcap's generated meshes into data/meshes/ (deterministic).

Every mesh is a closed, outward-oriented triangle 2-manifold (counter-clockwise
seen from outside).  Coordinates are printed with repr(), so re-running the
script reproduces the committed files byte for byte:

    python3 analysis/meshgen/generate_meshes.py [OUTPUT_DIR]
"""
import math
import os
import sys


def write_off(path, vertices, triangles, comment):
    with open(path, "w", encoding="ascii") as out:
        out.write("OFF\n")
        out.write(f"{len(vertices)} {len(triangles)} 0\n")
        for v in vertices:
            out.write(" ".join(repr(float(c)) for c in v) + "\n")
        for t in triangles:
            out.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    print(f"{path}: {len(triangles)} triangles ({comment})")


def cuboid(sx, sy, sz, cy=0.0):
    """Axis-aligned box of size sx*sy*sz centred at (0, cy, 0); 12 triangles."""
    hx, hy, hz = sx / 2, sy / 2, sz / 2
    v = [(x, cy + y, z) for x in (-hx, hx) for y in (-hy, hy) for z in (-hz, hz)]
    # vertex index = 4*ix + 2*iy + iz
    quads = [
        (0, 1, 3, 2),  # x = -hx, normal -x
        (4, 6, 7, 5),  # x = +hx
        (0, 4, 5, 1),  # y = -hy
        (2, 3, 7, 6),  # y = +hy
        (0, 2, 6, 4),  # z = -hz
        (1, 5, 7, 3),  # z = +hz
    ]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return v, tris


def sweep(n_around, profile, frame, seam_shift=0):
    """Closes a loop of cross-sections: profile(i) gives the section's 2-D
    points (counter-clockwise), frame(i, (u, w)) places one in 3-D.  At the
    seam, point k of the last section joins point k + seam_shift of the first
    (a twisted section comes back turned)."""
    verts = []
    m = len(profile(0))
    for i in range(n_around):
        for p in profile(i):
            verts.append(frame(i, p))
    tris = []
    for i in range(n_around):
        i2 = (i + 1) % n_around
        shift = seam_shift if i2 == 0 else 0
        for k in range(m):
            k2 = (k + 1) % m
            a, b = i * m + k, i * m + k2
            c, d = i2 * m + (k2 + shift) % m, i2 * m + (k + shift) % m
            tris += [(a, d, c), (a, c, b)]
    return verts, tris


def torus_frame(R):
    def frame(phi, p):
        r_off, y = p
        return ((R + r_off) * math.cos(phi), y, (R + r_off) * math.sin(phi))
    return frame


def torus(R, r, n_around, n_section):
    angles = [2 * math.pi * i / n_around for i in range(n_around)]
    section = [(r * math.cos(2 * math.pi * k / n_section), r * math.sin(2 * math.pi * k / n_section))
               for k in range(n_section)]
    frame = torus_frame(R)
    return sweep(n_around, lambda i: section, lambda i, p: frame(angles[i], p))


def twisted_torus(R, r, n_around, points, n_per_side, twists):
    """A star-shaped cross-section turned by `twists` full star periods along
    the loop: a 'twisted torus' like the ZP+ paper's occluder."""
    angles = [2 * math.pi * i / n_around for i in range(n_around)]
    n_section = points * 2 * n_per_side

    def profile(i):
        turn = twists * (2 * math.pi / points) * i / n_around
        pts = []
        for k in range(n_section):
            t = 2 * math.pi * k / n_section
            rho = r * (0.62 + 0.38 * math.cos(points * t))
            pts.append((rho * math.cos(t + turn), rho * math.sin(t + turn)))
        return pts

    frame = torus_frame(R)
    shift = twists * n_section // points
    return sweep(n_around, profile, lambda i, p: frame(angles[i], p), seam_shift=shift)


def orient_outward(verts, tris):
    """Flips every triangle if the signed volume is negative."""
    vol = 0.0
    for a, b, c in tris:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = verts[a], verts[b], verts[c]
        vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    if vol < 0:
        tris = [(a, c, b) for a, b, c in tris]
    return tris


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "data", "meshes")
    os.makedirs(out_dir, exist_ok=True)
    meshes = {
        "box.off": (cuboid(1, 1, 1), "unit cube [-1/2, 1/2]^3"),
        "ground.off": (cuboid(20, 0.25, 20, cy=-0.125), "slab 20 x 0.25 x 20, top face at y = 0"),
        "quad_slab.off": (cuboid(2, 0.125, 2), "thin slab 2 x 0.125 x 2"),
        "torus.off": (torus(1.0, 0.35, 48, 24), "R = 1, r = 0.35, 48 x 24"),
        "twisted_torus.off": (twisted_torus(1.0, 0.45, 120, 5, 5, 3), "5-point star section, 3 twists"),
    }
    for name, ((verts, tris), comment) in meshes.items():
        write_off(os.path.join(out_dir, name), verts, orient_outward(verts, tris), comment)


if __name__ == "__main__":
    main()
