#!/usr/bin/env python3
"""The reduced conveyor of Madden (2020): an annulus chamber fed through its floor, a plenum
above it, and the outlet tube on the axis. Writes the fluid mesh's blockMeshDict and the DEM's
STL walls from one set of dimensions, so the two describe the same surfaces.

    python3 geometry.py            # coarse mesh (CFD/system/blockMeshDict), DEM/meshes/conveyor.stl
    python3 geometry.py --fine     # every cell count doubled (8x the cells)
    python3 geometry.py --out DIR  # write the blockMeshDict into DIR instead

All lengths in metres; the axis is z, gravity -z. README.md gives the reasons for each number.
"""
import argparse
import math
import os

# --- dimensions (m), chosen: the seed gives none (README.md, "Geometry") ---
R_CORE = 0.015    # inner radius of the annulus (the solid core)
R_OUT = 0.025     # outer radius of the annulus and the plenum
R_TUBE = 0.005    # outlet tube radius (10 mm bore)
Z_LEDGE = 0.020   # top of the annulus = the core's top (the ledge), annulus floor at z = 0
Z_LID = 0.025     # plenum lid; the tube starts here
Z_OUT = 0.065     # tube outlet (tube length 40 mm = 4 bores)
SQUARE = 0.55 * R_TUBE  # corner radius of the O-grid's central square

# --- resolution (cells) for the coarse mesh; --fine doubles each ---
COARSE = dict(nt=6, n_sq_ring=3, n_tube_core=5, n_annulus=5, nz_annulus=10, nz_plenum=4, nz_tube=24)

HERE = os.path.dirname(os.path.abspath(__file__))


def block_mesh_dict(n):
    """blockMeshDict text: four z levels, at each 16 points (square corners, tube circle, core
    circle, outer circle at 45 + 90 q degrees); ring blocks per quadrant, one central square."""
    levels = [0.0, Z_LEDGE, Z_LID, Z_OUT]
    radii = [SQUARE, R_TUBE, R_CORE, R_OUT]

    def vid(level, ring, q):
        return 16 * level + 4 * ring + q % 4

    verts = []
    for z in levels:
        for r in radii:
            for q in range(4):
                a = math.radians(45 + 90 * q)
                verts.append((r * math.cos(a), r * math.sin(a), z))
    blocks, edges = [], []
    nz = [n["nz_annulus"], n["nz_plenum"], n["nz_tube"]]
    nr = [n["n_sq_ring"], n["n_tube_core"], n["n_annulus"]]
    # which rings each layer holds: 0 = central square, 1..3 = ring between radii[k-1], radii[k]
    layers = [[3], [0, 1, 2, 3], [0, 1]]
    for lay, rings in enumerate(layers):
        lo, hi = lay, lay + 1
        for k in rings:
            if k == 0:
                order = [2, 3, 0, 1]
                v = [vid(lo, 0, q) for q in order] + [vid(hi, 0, q) for q in order]
                blocks.append((v, (n["nt"], n["nt"], nz[lay])))
                continue
            for q in range(4):
                v = [vid(lo, k - 1, q), vid(lo, k, q), vid(lo, k, q + 1), vid(lo, k - 1, q + 1)]
                v += [vid(hi, k - 1, q), vid(hi, k, q), vid(hi, k, q + 1), vid(hi, k - 1, q + 1)]
                blocks.append((v, (nr[k - 1], n["nt"], nz[lay])))
    # arcs on every circle (rings 1..3) at every level where a block uses them
    used = {i for b, _ in blocks for i in b}
    for lev, z in enumerate(levels):
        for ring in (1, 2, 3):
            r = radii[ring]
            for q in range(4):
                a, b = vid(lev, ring, q), vid(lev, ring, q + 1)
                if a in used and b in used:
                    m = math.radians(90 + 90 * q)
                    edges.append((a, b, (r * math.cos(m), r * math.sin(m), z)))
    inlet = []
    for v, _ in blocks[:4]:  # the annulus blocks' floors
        inlet.append((v[0], v[3], v[2], v[1]))
    outlet = []
    for v, _ in blocks[-5:]:  # the tube blocks' tops
        outlet.append((v[4], v[5], v[6], v[7]))

    f = lambda x: f"{x:.10g}"
    out = ["/*--------------------------------*- C++ -*----------------------------------*\\",
           "  foamgrain reference case: reduced pneumatic conveyor (Madden 2020); written by",
           "  geometry.py (do not edit: change the script and run it again)",
           "\\*---------------------------------------------------------------------------*/",
           "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }",
           "",
           "convertToMeters 1;",
           "",
           "vertices", "("]
    out += [f"    ({f(x)} {f(y)} {f(z)}) // {i}" for i, (x, y, z) in enumerate(verts)]
    out += [");", "", "blocks", "("]
    for v, (a, b, c) in blocks:
        out.append(f"    hex ({' '.join(map(str, v))}) ({a} {b} {c}) simpleGrading (1 1 1)")
    out += [");", "", "edges", "("]
    for a, b, (x, y, z) in edges:
        out.append(f"    arc {a} {b} ({f(x)} {f(y)} {f(z)})")
    out += [");", "", "boundary", "("]
    for name, faces in (("inlet", inlet), ("outlet", outlet)):
        out += [f"    {name}", "    {", "        type patch;", "        faces", "        ("]
        out += [f"            ({' '.join(map(str, fc))})" for fc in faces]
        out += ["        );", "    }"]
    out += [");", "", "defaultPatch { name walls; type wall; }", "",
            "mergePatchPairs ();", ""]
    return "\n".join(out)


def stl(n_seg=48, dz=0.0025):
    """ASCII STL of every wall the particles meet, as one welded surface: the annulus floor
    (a screen: the air passes, the particles do not), the outer wall, the core's side and top
    (the ledge), the plenum lid and the tube. The outlet is open."""
    tris = []

    def circle(r, z, k):
        a = 2 * math.pi * k / n_seg
        return (r * math.cos(a), r * math.sin(a), z)

    def cylinder(r, z0, z1):
        m = max(1, round((z1 - z0) / dz))
        for j in range(m):
            za, zb = z0 + (z1 - z0) * j / m, z0 + (z1 - z0) * (j + 1) / m
            for k in range(n_seg):
                a, b = circle(r, za, k), circle(r, za, k + 1)
                c, d = circle(r, zb, k + 1), circle(r, zb, k)
                tris.append((a, b, c))
                tris.append((a, c, d))

    def ring(r0, r1, z, rings):
        # flat annulus r0..r1 in `rings` bands (r0 = 0: a disk)
        for j in range(rings):
            ra, rb = r0 + (r1 - r0) * j / rings, r0 + (r1 - r0) * (j + 1) / rings
            for k in range(n_seg):
                if ra == 0.0:
                    tris.append(((0.0, 0.0, z), circle(rb, z, k), circle(rb, z, k + 1)))
                    continue
                a, b = circle(ra, z, k), circle(ra, z, k + 1)
                c, d = circle(rb, z, k + 1), circle(rb, z, k)
                tris.append((a, b, c))
                tris.append((a, c, d))

    ring(R_CORE, R_OUT, 0.0, 4)               # screen floor of the annulus
    cylinder(R_OUT, 0.0, Z_LID)               # outer wall (annulus + plenum)
    cylinder(R_CORE, 0.0, Z_LEDGE)            # core side
    ring(0.0, R_CORE, Z_LEDGE, 6)             # core top: the ledge
    ring(R_TUBE, R_OUT, Z_LID, 8)             # plenum lid
    cylinder(R_TUBE, Z_LID, Z_OUT)            # outlet tube
    lines = ["solid conveyor"]
    for a, b, c in tris:
        ux, uy, uz = (b[i] - a[i] for i in range(3))
        vx, vy, vz = (c[i] - a[i] for i in range(3))
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        s = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
        lines.append(f"  facet normal {nx / s:.6e} {ny / s:.6e} {nz / s:.6e}")
        lines.append("    outer loop")
        for p in (a, b, c):
            lines.append(f"      vertex {p[0]:.9e} {p[1]:.9e} {p[2]:.9e}")
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid conveyor")
    return "\n".join(lines) + "\n", len(tris)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fine", action="store_true", help="double every cell count")
    ap.add_argument("--out", default=os.path.join(HERE, "CFD/system"),
                    help="directory for blockMeshDict")
    a = ap.parse_args()
    n = {k: v * (2 if a.fine else 1) for k, v in COARSE.items()}
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "blockMeshDict"), "w") as fh:
        fh.write(block_mesh_dict(n))
    text, count = stl()
    os.makedirs(os.path.join(HERE, "DEM/meshes"), exist_ok=True)
    with open(os.path.join(HERE, "DEM/meshes/conveyor.stl"), "w") as fh:
        fh.write(text)
    print(f"blockMeshDict in {a.out}; DEM/meshes/conveyor.stl: {count} triangles")


if __name__ == "__main__":
    main()
