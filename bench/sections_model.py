#!/usr/bin/python3
"""Benchmark models (not a test) for bench/sections.sh: a reinforced concrete
block analysed with its embedded steel, against the same block alone, both
with the same total element count.

usage: sections_model.py [WORK] [TARGET]    (defaults /tmp/dtmap-sections-bench, 1e6)

Mixed model (OpenCASCADE, SI units): a W x W x L block (1 x 1 x 4 m) with
- 4 x 4 longitudinal bars (x, y at 0.1, 0.367, 0.633, 0.9; z from 0.05 to
  3.95), straight lines;
- transverse links every 0.2 m (z = 0.1 ... 3.9): at each level one line along
  x through every row of bars and one along y through every column, so each
  level is a grid through the 16 bars;
- 3 plates, 0.9 x 0.9 m rectangles at z = 1, 2, 3 (between two link levels),
  pierced by the 16 bars.
Everything is fragmented with the block (OpenCASCADE's general fuse), so the
lines and rectangles are embedded in the volume, crossings become shared
points, and the triangles and line elements share their nodes with the
tetrahedra. Physical groups: "concrete" (volume), "rebar" (every bar and link
piece), "plate" (the rectangles). The solid-only model is the same block
alone, group "concrete".

Both are meshed by Gmsh's Delaunay on one thread (Mesh.Algorithm3D = 1,
General.NumThreads = 1, Gmsh's default optimiser) at a uniform size
(Mesh.MeshSizeMax), written as binary MSH 4.1 (only the physical groups'
elements, Gmsh's default). The first size comes from the element density
measured at 1e6 (per m^3, N h^3 = 4.8 for the mixed total, 4.53 for the
solid's tets; a coarse calibration mesh misled by 30 %: the 0.2 m link grid
and the boundary weigh more there), then the size is corrected (N ~ h^-3)
and the model remeshed, at most twice, until tets + lines + triangles is
within 3 % of TARGET, and the solid's tets within 1 % of the mixed total.

Writes WORK/mixed_T.msh, WORK/solid_T.msh and WORK/models_T.json (T the
target as given, e.g. 1e6: element counts per type, nodes, sizes, meshing
seconds) and prints that JSON; when the three exist they are reused and only
the JSON is printed.
"""
import json
import os
import sys
import time

import gmsh

W, L = 1.0, 4.0
BARS = (0.1, 0.1 + 0.8 / 3, 0.1 + 1.6 / 3, 0.9)  # x (and y) of the 4 x 4 bars
BAR_Z = (0.05, L - 0.05)
LINKS = [0.1 + 0.2 * k for k in range(20)]  # z of the link levels
PLATES_Z = (1.0, 2.0, 3.0)
PLATE = (0.05, 0.95)  # x and y extent of each plate
TOL_SOLID = 0.01  # relative mismatch of the solid's tets to the mixed total
TOL_MIXED = 0.03  # of the mixed total to the target
DENSITY_MIXED, DENSITY_SOLID = 4.8, 4.53  # N h^3 per m^3 at 1e6 (Delaunay, this model)


def log(msg):
    print(f"sections_model: {msg}", file=sys.stderr, flush=True)


def options():
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.Verbosity", 2)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)


def build(mixed):
    """The geometry of the current model and its physical groups."""
    occ = gmsh.model.occ
    box = occ.addBox(0, 0, 0, W, W, L)
    if not mixed:
        occ.synchronize()
        _group(3, [box], "concrete")
        return
    lines = []
    for x in BARS:
        for y in BARS:
            lines.append(occ.addLine(occ.addPoint(x, y, BAR_Z[0]), occ.addPoint(x, y, BAR_Z[1])))
    for z in LINKS:
        for v in BARS:
            lines.append(occ.addLine(occ.addPoint(BARS[0], v, z), occ.addPoint(BARS[-1], v, z)))  # along x
            lines.append(occ.addLine(occ.addPoint(v, BARS[0], z), occ.addPoint(v, BARS[-1], z)))  # along y
    plates = [occ.addRectangle(PLATE[0], PLATE[0], z, PLATE[1] - PLATE[0], PLATE[1] - PLATE[0]) for z in PLATES_Z]
    tools = [(1, l) for l in lines] + [(2, s) for s in plates]
    _, children = occ.fragment([(3, box)], tools)
    occ.synchronize()
    vol = sorted({t for d, t in children[0] if d == 3})
    rebar = sorted({t for m in children[1:1 + len(lines)] for d, t in m if d == 1})
    plate = sorted({t for m in children[1 + len(lines):] for d, t in m if d == 2})
    if len(vol) != 1 or not rebar or len(plate) != len(plates):
        sys.exit(f"sections_model: unexpected fragments: {len(vol)} volumes, {len(rebar)} curves, {len(plate)} surfaces")
    _group(3, vol, "concrete")
    _group(1, rebar, "rebar")
    _group(2, plate, "plate")


def _group(dim, tags, name):  # Gmsh 4.8's addPhysicalGroup takes no name
    g = gmsh.model.addPhysicalGroup(dim, tags)
    gmsh.model.setPhysicalName(dim, g, name)


def counts():
    """Elements per type in the physical groups (what the .msh holds), and nodes."""
    out, nodes = {}, set()
    for dim, g in gmsh.model.getPhysicalGroups():
        for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, g):
            types, tags, conn = gmsh.model.mesh.getElements(dim, ent)
            for t, tg, c in zip(types, tags, conn):
                name = gmsh.model.mesh.getElementProperties(t)[0].split()[0].lower()
                name = {"tetrahedron": "tet4", "triangle": "tri3", "line": "line2"}.get(name, name)
                out[name] = out.get(name, 0) + len(tg)
                nodes.update(c.tolist())
    out["total"] = sum(out.values())
    out["nodes"] = len(nodes)
    return out


def mesh(h):
    gmsh.model.mesh.clear()
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0)
    t0 = time.perf_counter()
    gmsh.model.mesh.generate(3)
    t = time.perf_counter() - t0
    c = counts()
    log(f"  h = {h:.5f}: {c} in {t:.1f} s")
    return c, t


def first_size(target, per_m3):
    """The size that gives target elements at per_m3 / h^3 elements per m^3."""
    return (per_m3 * W * W * L / target)**(1 / 3)


def make(mixed, target, h, tol, name):
    """Mesh the model at size h, correcting it until the count (tets for the
    solid, all for the mixed) is within tol of target, at most twice."""
    gmsh.model.add(name)
    build(mixed)
    key = "total" if mixed else "tet4"
    for attempt in range(3):
        c, t = mesh(h)
        ratio = c[key] / target
        if abs(ratio - 1) <= tol or attempt == 2:
            return c, t, h
        h *= ratio**(1 / 3)


def write(path):
    tmp = path + ".part.msh"
    gmsh.write(tmp)
    os.replace(tmp, path)


def main():
    work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/dtmap-sections-bench"
    tag = sys.argv[2] if len(sys.argv) > 2 else "1e6"
    target = float(tag)
    os.makedirs(work, exist_ok=True)
    mixed_msh, solid_msh = os.path.join(work, f"mixed_{tag}.msh"), os.path.join(work, f"solid_{tag}.msh")
    info_json = os.path.join(work, f"models_{tag}.json")
    if all(os.path.exists(p) for p in (mixed_msh, solid_msh, info_json)):
        log(f"reusing {mixed_msh}, {solid_msh}")
        print(open(info_json).read().strip())
        return
    gmsh.initialize(["sections_model.py"])
    options()
    log(f"mixed model, target {target:.3g} elements")
    mc, mt, mh = make(True, target, first_size(target, DENSITY_MIXED), TOL_MIXED, "mixed")
    write(mixed_msh)
    gmsh.model.remove()
    log(f"solid model, target {mc['total']} tets")  # its tets match the mixed total
    sc, st, sh = make(False, mc["total"], first_size(mc["total"], DENSITY_SOLID), TOL_SOLID, "solid")
    write(solid_msh)
    version = gmsh.option.getString("General.Version")
    gmsh.finalize()
    info = {
        "target": target,
        "gmsh": version,
        "mixed": dict(file=os.path.basename(mixed_msh), size=mh, mesh_seconds=mt, **mc),
        "solid": dict(file=os.path.basename(solid_msh), size=sh, mesh_seconds=st, **sc),
    }
    with open(info_json + ".part", "w") as f:
        json.dump(info, f)
    os.replace(info_json + ".part", info_json)
    print(json.dumps(info))


main()
