#!/usr/bin/env python3
"""The conveyor of Madden (2020): an annulus chamber fed through its floor, a plenum above it,
and the outlet tube on the axis (the reduced geometry); with --full, the tube continued
downstream to a T branch whose +x leg vents through the outlet (held below ambient) and whose
-x leg ends in a closed secondary chamber (../pneumatic-conveying-full). Writes the fluid mesh's
blockMeshDict and the DEM's STL walls from one set of dimensions, so the two describe the same
surfaces.

    python3 geometry.py            # coarse mesh (CFD/system/blockMeshDict), DEM/meshes/conveyor.stl
    python3 geometry.py --fine     # every cell count doubled (8x the cells)
    python3 geometry.py --scale S  # every cell count times S (2.13: ~5e4 cells, the seed's coarse)
    python3 geometry.py --out DIR  # write the blockMeshDict into DIR instead
    python3 geometry.py --full [--scale S]   # the full system into ../pneumatic-conveying-full;
                                   # every cell count times S (1: ~2.4e4 cells; 0.5: the CI mesh)

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

# --- the full system (--full; ../pneumatic-conveying-full/README.md gives the reasons) ---
Z_SQ = 0.145      # the downstream tube ends (tube 120 mm = 12 bores from the lid)
Z_J0 = 0.155      # round-to-square transition ends: the branch's floor
HALF = 0.0045     # half-side of the square ducts (9 x 9 mm, area 81 mm2 ~ the tube's 78.5)
Z_J1 = Z_J0 + 2 * HALF  # the branch's roof
X_VENT = HALF + 0.040   # +x leg: 40 mm duct to the vented outlet
X_LEG = -HALF - 0.020   # -x leg: 20 mm duct to the secondary chamber
X_CH = X_LEG - 0.030    # secondary chamber: x X_CH ... X_LEG,
Y_CH = 0.015            # y -Y_CH ... Y_CH,
Z_CH = Z_J1 - 0.030     # z Z_CH ... Z_J1 (30 mm cube, roof flush with the ducts')
# cells of the downstream parts for scale 1 (about the reduced coarse mesh's 1.67 mm axially)
FULL = dict(nz_down=48, nz_trans=6, nz_branch=6, nx_vent=27, nx_leg=13, nx_ch=20, ny_ch=7,
            nz_ch=14)

# --- resolution (cells) for the coarse mesh; --fine doubles each ---
COARSE = dict(nt=6, n_sq_ring=3, n_tube_core=5, n_annulus=5, nz_annulus=10, nz_plenum=4, nz_tube=24)

HERE = os.path.dirname(os.path.abspath(__file__))


def block_mesh_dict(n, full=False):
    """blockMeshDict text: four z levels (seven with `full`), at each 16 points (square
    corners, tube circle, core circle, outer circle at 45 + 90 q degrees); ring blocks per
    quadrant, one central square. With `full` the tube's circle becomes the square of half-side
    HALF over the transition, and the branch, its two legs and the chamber follow
    (`branch_blocks`)."""
    levels = [0.0, Z_LEDGE, Z_LID, Z_OUT] + ([Z_SQ, Z_J0, Z_J1] if full else [])
    radii = [SQUARE, R_TUBE, R_CORE, R_OUT]
    square_from = 5  # levels from here on: the tube's circle is the branch's square

    def vid(level, ring, q):
        return 16 * level + 4 * ring + q % 4

    verts = []
    for lev, z in enumerate(levels):
        for ring, r in enumerate(radii):
            for q in range(4):
                a = math.radians(45 + 90 * q)
                if ring == 1 and lev >= square_from:
                    verts.append((math.copysign(HALF, math.cos(a)),
                                  math.copysign(HALF, math.sin(a)), z))
                    continue
                verts.append((r * math.cos(a), r * math.sin(a), z))
    blocks, edges = [], []
    nz = [n["nz_annulus"], n["nz_plenum"], n["nz_tube"]]
    nr = [n["n_sq_ring"], n["n_tube_core"], n["n_annulus"]]
    # which rings each layer holds: 0 = central square, 1..3 = ring between radii[k-1], radii[k]
    layers = [[3], [0, 1, 2, 3], [0, 1]]
    if full:
        nz += [n["nz_down"], n["nz_trans"], n["nz_branch"]]
        layers += [[0, 1]] * 3
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
                if a in used and b in used and not (ring == 1 and lev >= square_from):
                    m = math.radians(90 + 90 * q)
                    edges.append((a, b, (r * math.cos(m), r * math.sin(m), z)))
    inlet = []
    for v, _ in blocks[:4]:  # the annulus blocks' floors
        inlet.append((v[0], v[3], v[2], v[1]))
    outlet = []
    if full:
        junction = blocks[-4:]  # the branch layer's ring blocks, q = 0 .. 3
        outlet = branch_blocks(n, verts, blocks, junction)
    else:
        for v, _ in blocks[-5:]:  # the tube blocks' tops
            outlet.append((v[4], v[5], v[6], v[7]))

    f = lambda x: f"{x:.10g}"
    what = "full" if full else "reduced"
    out = ["/*--------------------------------*- C++ -*----------------------------------*\\",
           f"  foamgrain reference case: {what} pneumatic conveyor (Madden 2020); written by",
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


def branch_blocks(n, verts, blocks, junction):
    """Appends the full system's blocks past the branch (the square junction of the tube's last
    layer, `junction`: its ring blocks q = 0..3, q = 3 facing +x, q = 1 facing -x) to `blocks`
    and their new points to `verts`: the +x leg to the vented outlet, the -x leg and the
    secondary chamber (3 x 2 blocks around the leg's end, closed). Returns the outlet's faces."""
    index = {}
    for i, p in enumerate(verts):
        index.setdefault(p, i)

    def pt(x, y, z):
        p = (x, y, z)
        if p not in index:
            index[p] = len(verts)
            verts.append(p)
        return index[p]

    def box(x0, x1, y0, y1, z0, z1, cells):
        v = [pt(x0, y0, z0), pt(x1, y0, z0), pt(x1, y1, z0), pt(x0, y1, z0),
             pt(x0, y0, z1), pt(x1, y0, z1), pt(x1, y1, z1), pt(x0, y1, z1)]
        blocks.append((v, cells))
        return v

    # the legs attach to the junction blocks' outer faces: nt cells across, nz_branch up
    for q, x in ((3, HALF), (1, -HALF)):
        v, _ = junction[q]
        face = {verts[i] for i in (v[1], v[2], v[5], v[6])}
        assert face == {(x, s * HALF, z) for s in (-1, 1) for z in (Z_J0, Z_J1)}, face
    nt, nzb = n["nt"], n["nz_branch"]
    vent = box(HALF, X_VENT, -HALF, HALF, Z_J0, Z_J1, (n["nx_vent"], nt, nzb))
    box(X_LEG, -HALF, -HALF, HALF, Z_J0, Z_J1, (n["nx_leg"], nt, nzb))
    ys, ny = [-Y_CH, -HALF, HALF, Y_CH], [n["ny_ch"], nt, n["ny_ch"]]
    zs, nzc = [Z_CH, Z_J0, Z_J1], [n["nz_ch"], nzb]
    for j in range(3):
        for k in range(2):
            box(X_CH, X_LEG, ys[j], ys[j + 1], zs[k], zs[k + 1], (n["nx_ch"], ny[j], nzc[k]))
    return [(vent[1], vent[2], vent[6], vent[5])]


def stl(n_seg=48, dz=0.0025, full=False):
    """ASCII STL of every wall the particles meet, as one welded surface: the annulus floor
    (a screen: the air passes, the particles do not), the outer wall, the core's side and top
    (the ledge), the plenum lid and the tube. The outlet is open. With `full`, the tube goes on
    to Z_SQ, then the transition (ruled from the circle to the square, point k of a quarter
    circle to point k of the square's side, as blockMesh's edges), the branch's roof and sides,
    both legs and the closed chamber (`branch_walls`); the vented outlet is open."""
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
    cylinder(R_TUBE, Z_LID, Z_SQ if full else Z_OUT)  # outlet tube
    if full:
        branch_walls(tris, circle, n_seg, dz)
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


def branch_walls(tris, circle, n_seg, dz):
    """The full system's walls past the tube (`stl`), appended to `tris`."""
    def lerp(p, q, t):
        return tuple(a + (b - a) * t for a, b in zip(p, q))

    def quad(a, b, c, d):
        tris.append((a, b, c))
        tris.append((a, c, d))

    # transition: the circle at Z_SQ to the square at Z_J0, in dz rows
    corner = [(math.copysign(HALF, math.cos(a)), math.copysign(HALF, math.sin(a)), Z_J0)
              for a in (math.radians(45 + 90 * q) for q in range(4))]
    per_q = n_seg // 4
    m = max(1, round((Z_J0 - Z_SQ) / dz))
    for q in range(4):
        for j in range(per_q):
            k = n_seg // 8 + per_q * q + j
            lo = [circle(R_TUBE, Z_SQ, k), circle(R_TUBE, Z_SQ, k + 1)]
            hi = [lerp(corner[q], corner[(q + 1) % 4], t / per_q) for t in (j, j + 1)]
            for i in range(m):
                a, b = lerp(lo[0], hi[0], i / m), lerp(lo[1], hi[1], i / m)
                c, d = lerp(lo[1], hi[1], (i + 1) / m), lerp(lo[0], hi[0], (i + 1) / m)
                quad(a, b, c, d)

    def rect(p0, e1, e2):
        # the rectangle p0 + s e1 + t e2 (s, t in 0..1), in cells of about dz
        n1 = max(1, round(math.dist((0, 0, 0), e1) / dz))
        n2 = max(1, round(math.dist((0, 0, 0), e2) / dz))
        at = lambda s, t: tuple(p0[i] + s * e1[i] + t * e2[i] for i in range(3))
        for i in range(n1):
            for j in range(n2):
                quad(at(i / n1, j / n2), at((i + 1) / n1, j / n2),
                     at((i + 1) / n1, (j + 1) / n2), at(i / n1, (j + 1) / n2))

    h = Z_J1 - Z_J0
    for y in (-HALF, HALF):  # the branch's and both legs' side walls
        rect((X_LEG, y, Z_J0), (X_VENT - X_LEG, 0, 0), (0, 0, h))
    rect((X_LEG, -HALF, Z_J1), (X_VENT - X_LEG, 0, 0), (0, 2 * HALF, 0))  # roofs
    rect((X_LEG, -HALF, Z_J0), (-HALF - X_LEG, 0, 0), (0, 2 * HALF, 0))   # -x leg's floor
    rect((HALF, -HALF, Z_J0), (X_VENT - HALF, 0, 0), (0, 2 * HALF, 0))    # +x leg's floor
    # the secondary chamber: a closed box but for the leg's opening
    w, d, hc = 2 * Y_CH, X_LEG - X_CH, Z_J1 - Z_CH
    rect((X_CH, -Y_CH, Z_CH), (0, w, 0), (0, 0, hc))                      # far wall
    for y in (-Y_CH, Y_CH):
        rect((X_CH, y, Z_CH), (d, 0, 0), (0, 0, hc))                      # sides
    for z in (Z_CH, Z_J1):
        rect((X_CH, -Y_CH, z), (d, 0, 0), (0, w, 0))                      # floor, roof
    rect((X_LEG, -Y_CH, Z_CH), (0, Y_CH - HALF, 0), (0, 0, hc))           # the leg's wall,
    rect((X_LEG, HALF, Z_CH), (0, Y_CH - HALF, 0), (0, 0, hc))            # around its
    rect((X_LEG, -HALF, Z_CH), (0, 2 * HALF, 0), (0, 0, Z_J0 - Z_CH))     # opening


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fine", action="store_true", help="double every cell count")
    ap.add_argument("--out", help="directory for blockMeshDict (default: the case's CFD/system)")
    ap.add_argument("--full", action="store_true",
                    help="the full system, into ../pneumatic-conveying-full")
    ap.add_argument("--scale", type=float, default=1.0,
                    help="every cell count times this (rounded, at least 1)")
    a = ap.parse_args()
    case = os.path.join(os.path.dirname(HERE), "pneumatic-conveying-full") if a.full else HERE
    if a.full:
        n = {k: max(1, int(v * a.scale + 0.5)) for k, v in {**COARSE, **FULL}.items()}
    else:
        f = a.scale * (2 if a.fine else 1)
        n = {k: max(1, int(v * f + 0.5)) for k, v in COARSE.items()}
    out = a.out or os.path.join(case, "CFD/system")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "blockMeshDict"), "w") as fh:
        fh.write(block_mesh_dict(n, a.full))
    text, count = stl(full=a.full)
    os.makedirs(os.path.join(case, "DEM/meshes"), exist_ok=True)
    with open(os.path.join(case, "DEM/meshes/conveyor.stl"), "w") as fh:
        fh.write(text)
    print(f"blockMeshDict in {out}; {case}/DEM/meshes/conveyor.stl: {count} triangles")


if __name__ == "__main__":
    main()
