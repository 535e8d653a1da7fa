"""Bring the real-CAD corpus of bench/cad/parts.tsv into a directory.

Each part is read from its source: a gzipped file of Debian's gmsh-doc
package, or a file of a public GitHub repository at a fixed commit, read from
a local mirror of it (`git --git-dir=MIRRORS/owner+name/repo show commit:path`).
A part that is one solid of an assembly is cut out with Gmsh's OpenCASCADE
kernel (the solid whose volume matches the table's, within 1 %) and written
as a .brep in millimetres; other parts keep their own file and format. Then
each part gets a wrapper .geo that scales it to metres, because dtmap takes
a geometry's coordinates as metres: STEP through Geometry.OCCTargetUnit (the
file names its unit), BREP (no unit; these are in millimetres) by a uniform
scale of 1e-3 about the origin.

The parts are public files kept out of the repository: this script, the
table and the mirrors make them again, and their SHA-256 are checked
against bench/cad/parts.sha256 when it lists them.

Usage: corpus.py OUT_DIR [--mirrors DIR]   (default /work/.mirror)
Prints, and writes to OUT_DIR/parts.list, one line per part: name, file, format,
solids, volume (mm^3), bounding box (mm), SHA-256.
"""

import gzip
import hashlib
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def table():
    rows = []
    for line in open(os.path.join(HERE, "parts.tsv"), encoding="utf-8"):
        if line.startswith("#") or not line.strip():
            continue
        cells = line.rstrip("\n").split("\t")
        cells += [""] * (7 - len(cells))
        name, kind, source, commit, path, licence, solid = cells[:7]
        rows.append(dict(name=name, kind=kind, source=source, commit=commit, path=path, licence=licence,
                         solid=float(solid) if solid.strip() else None))
    return rows


def raw_bytes(row, mirrors):
    if row["source"].startswith("debian:"):
        with gzip.open(row["path"], "rb") as f:
            return f.read()
    git_dir = os.path.join(mirrors, row["source"].replace("/", "+"), "repo")
    return subprocess.run(["git", "--git-dir", git_dir, "show", "%s:%s" % (row["commit"], row["path"])],
                          check=True, stdout=subprocess.PIPE).stdout


def suffix(path):
    p = path[:-3] if path.endswith(".gz") else path
    return os.path.splitext(p)[1].lower()


def cut_solid(src, dst, volume):
    """Keep the solid of src whose volume is within 1 % of volume; write it to dst (.brep)."""
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.model.occ.importShapes(src)
        gmsh.model.occ.synchronize()
        vols = [t for _, t in gmsh.model.getEntities(3)]
        keep = [t for t in vols if abs(gmsh.model.occ.getMass(3, t) - volume) <= 0.01 * volume]
        if not keep:
            raise SystemExit("%s: no solid of volume %g mm^3" % (src, volume))
        gmsh.model.occ.remove([(3, t) for t in vols if t != keep[0]], recursive=True)
        gmsh.model.occ.synchronize()
        gmsh.write(dst)
    finally:
        gmsh.finalize()


def describe(path):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        gmsh.model.occ.importShapes(path)
        gmsh.model.occ.synchronize()
        vols = [t for _, t in gmsh.model.getEntities(3)]
        v = sum(gmsh.model.occ.getMass(3, t) for t in vols)
        b = gmsh.model.getBoundingBox(-1, -1)
        return len(vols), v, [b[3] - b[0], b[4] - b[1], b[5] - b[2]]
    finally:
        gmsh.finalize()


def wrapper(name, part_file, fmt):
    if fmt in (".step", ".stp"):
        body = 'Geometry.OCCTargetUnit = "M";\nMerge "%s";\n' % part_file
    else:
        body = ('SetFactory("OpenCASCADE");\nv() = ShapeFromFile("%s");\n'
                "Dilate {{0, 0, 0}, 0.001} { Volume{v()}; }\n" % part_file)
    return "// %s in metres (written by bench/cad/corpus.py)\n%s" % (name, body)


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        sys.exit(__doc__)
    out = os.path.abspath(args[0])
    mirrors = args[args.index("--mirrors") + 1] if "--mirrors" in args else "/work/.mirror"
    os.makedirs(os.path.join(out, "src"), exist_ok=True)
    sums = {}
    sums_file = os.path.join(HERE, "parts.sha256")
    if os.path.exists(sums_file):
        for line in open(sums_file):
            h, f = line.split()
            sums[f] = h
    lines = []
    for row in table():
        name = row["name"]
        data = raw_bytes(row, mirrors)
        fmt = suffix(row["path"])
        raw = os.path.join(out, "src", name + fmt)
        with open(raw, "wb") as f:
            f.write(data)
        if row["solid"] is not None:
            part = name + ".brep"
            cut_solid(raw, os.path.join(out, part), row["solid"])
            fmt = ".brep"
        else:
            part = name + fmt
            with open(os.path.join(out, part), "wb") as f:
                f.write(data)
        digest = hashlib.sha256(open(os.path.join(out, part), "rb").read()).hexdigest()
        if part in sums and sums[part] != digest:
            if row["solid"] is None:
                sys.exit("%s: SHA-256 %s differs from parts.sha256 (%s)" % (part, digest, sums[part]))
            print("%s: the solid cut here differs from parts.sha256's (another Gmsh than 4.8.4?)" % part,
                  file=sys.stderr)
        with open(os.path.join(out, name + ".geo"), "w") as f:
            f.write(wrapper(name, part, fmt))
        nvol, v, box = describe(os.path.join(out, part))
        lines.append("%s\t%s\t%s\t%d\t%.6g\t%.4g x %.4g x %.4g\t%s" % (name, part, fmt[1:], nvol, v, box[0], box[1],
                                                                     box[2], digest))
        print(lines[-1], flush=True)
    with open(os.path.join(out, "parts.list"), "w") as f:
        f.write("".join(line + "\n" for line in lines))


if __name__ == "__main__":
    main()
