#!/usr/bin/python3
"""The table "Gmsh's surface models in 3D" of docs/sections.md: every tutorial
and demo of Debian's gmsh-doc whose model is a surface (model dimension 2),
meshed by `dtmap run` with Gmsh's defaults (<meshing dim="2">) and run as a new
user would, in steel (E 210e9 Pa, nu 0.3, rho 7850 kg/m^3):

- with the default formulation (plane strain): refused when the surfaces are not
  plane and parallel, else analysed in one plane or in several parallel ones;
- with <section default="true" kind="membrane" thickness="0.01"/>; on a plane
  model also as plane stress, which a membrane in the model's plane equals;
- with kind="shell" (thickness 0.01, --posterior): elements, element bound,
  nodal bound and global step; when curve groups are left out (the model's bars,
  the report's mesh.left_out), again with them as trusses (area 1e-4 m^2).

"out of plane / size" is the largest distance of a node from the plane of the
largest element over the largest side of the model's bounding box (Gmsh's
Python API on the membrane run's mesh).

usage: bench/surface_models.py DTMAP [--write] [--examples DIR] [MODEL ...]
  (MODEL: a path under DIR such as tutorial/t12.geo; default: every
  tutorial/*.geo and demos/*/*.geo whose model is a surface). --write replaces
  the table in docs/sections.md; without it the table is printed.
"""

import argparse
import glob
import gzip
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "sections.md")
HEADING = "## Gmsh's surface models in 3D"
STEEL = '<material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>'
HEADER = ("| model | out of plane / size | default (plane strain) | membrane | "
          "shell: elements, element / nodal / global step (s) |\n|---|---|---|---|---|\n")


def uncompressed_copy(src, work):
    """gmsh-doc compresses some examples (t1.geo.gz, t13_data.stl.gz): a plain copy."""
    dst = os.path.join(work, "examples")
    shutil.copytree(src, dst)
    for gz in glob.glob(os.path.join(dst, "**", "*.gz"), recursive=True):
        with gzip.open(gz, "rb") as f, open(gz[:-3], "wb") as g:
            shutil.copyfileobj(f, g)
        os.remove(gz)
    return dst


PROBE = """import gmsh, sys
gmsh.initialize(["probe", "-v", "0"])
gmsh.open(sys.argv[1])
print(gmsh.model.getDimension())
"""


def model_dim(path):
    """The model's dimension as Gmsh opens it (a child process: some demos are slow or crash)."""
    try:
        p = subprocess.run([sys.executable, "-c", PROBE, os.path.basename(path)], cwd=os.path.dirname(path),
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, universal_newlines=True, timeout=120)
        return int(p.stdout.split()[-1])
    except (subprocess.TimeoutExpired, ValueError, IndexError):
        return -1


def run(dtmap, work, name, geo, body, formulation="", extra=()):
    """`dtmap run` on a scene; (exit code, its output, its report or None)."""
    xml = os.path.join(work, name + ".xml")
    with open(xml, "w") as f:
        f.write('<dtmap-scene version="1">\n  <geometry file="%s"/>\n  <meshing dim="2"/>\n  %s\n  %s\n'
                '  <effects><elastic %s/></effects>\n</dtmap-scene>\n' % (geo, STEEL, body, formulation))
    rep = os.path.join(work, name + ".json")
    p = subprocess.run([dtmap, "run", xml, "-o", os.path.join(work, name + ".msh"), "--report", rep] + list(extra),
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=1800)
    report = None
    if p.returncode == 0:
        with open(rep) as f:
            report = json.load(f)
    return p.returncode, p.stdout, report


def out_of_plane(msh):
    """Largest node distance from the largest surface element's plane over the model's largest side."""
    import gmsh
    gmsh.initialize(["surface_models", "-v", "0"])
    try:
        gmsh.open(msh)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        at = {int(t): (xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]) for i, t in enumerate(tags)}
        best, normal, origin, used = 0, None, None, set()
        for etype, _, nodes in zip(*gmsh.model.mesh.getElements(2)):
            nn = gmsh.model.mesh.getElementProperties(etype)[3]
            nc = 3 if nn in (3, 6) else 4
            for e in range(len(nodes) // nn):
                ids = [int(n) for n in nodes[e * nn:(e + 1) * nn]]
                used.update(ids)
                p = [at[i] for i in ids[:nc]]
                n = [0.0, 0.0, 0.0]
                for k in range(nc):
                    a, b = p[k], p[(k + 1) % nc]
                    n[0] += (a[1] - b[1]) * (a[2] + b[2])
                    n[1] += (a[2] - b[2]) * (a[0] + b[0])
                    n[2] += (a[0] - b[0]) * (a[1] + b[1])
                size = math.sqrt(sum(c * c for c in n))
                if size > best:
                    best, normal, origin = size, [c / size for c in n], p[0]
        pts = [at[i] for i in used]
        side = max(max(q[d] for q in pts) - min(q[d] for q in pts) for d in range(3))
        off = max(abs(sum((q[d] - origin[d]) * normal[d] for d in range(3))) for q in pts)
        return off / side
    finally:
        gmsh.finalize()


def default_cell(code, out):
    if code == 2 and "not plane and parallel" in out:
        return "exit 2, not plane"
    if code:
        return "exit %d" % code
    planes = [l for l in out.splitlines() if "parallel planes" in l]
    if planes:
        return "runs (%s parallel planes)" % planes[0].split("analysed in ")[1].split(" ")[0]
    return "runs (plane)"


def reason(out):
    """dtmap's error without the scene's path and the element's place."""
    text = out.strip().splitlines()[-1].replace("dtmap: error: ", "")
    text = re.sub(r"^\S*\.xml(:\d+)?: ", "", text)
    text = re.sub(r"^effect '[^']*' on element .*? at \([^)]*\): ", "", text)
    return text[:150].replace("|", "/")


def shell_cell(code, rep, out, trusses):
    if code:
        return "exit %d: %s" % (code, reason(out))
    dt = rep["dt"]
    return "%d; %s / %s / %s%s" % (rep["mesh"]["elements"], sci(dt["min"]), sci(dt["nodal"]), sci(dt["global"]),
                                   " (curve groups %s as trusses, A = 1e-4 m^2)" % trusses if trusses else "")


def sci(v):
    """3 significant digits as 1.63e-4."""
    m, e = ("%.2e" % v).split("e")
    return "%se%d" % (m, int(e))


def model_row(dtmap, work, examples, model):
    geo = os.path.join(examples, model)
    name = model.replace("/", "_")[:-4]
    code, out, _ = run(dtmap, work, name + "_default", geo, "", 'formulation="plane-strain"')
    default = default_cell(code, out)
    membrane = '<section default="true" kind="membrane" thickness="0.01"/>'
    mcode, mout, mrep = run(dtmap, work, name + "_membrane", geo, membrane)
    mem = "runs" if mcode == 0 else "exit %d" % mcode
    if mcode == 0 and code == 0 and "parallel" not in default:
        scode, _, srep = run(dtmap, work, name + "_stress", geo, "", 'formulation="plane-stress"')
        if scode == 0 and abs(srep["dt"]["min"] / mrep["dt"]["min"] - 1) < 1e-12:
            mem = "runs (= plane stress)"
    ratio = out_of_plane(os.path.join(work, name + "_membrane.msh")) if mcode == 0 else float("nan")
    shell = '<section default="true" kind="shell" thickness="0.01"/>'
    scode, sout, srep = run(dtmap, work, name + "_shell", geo, shell, extra=["--posterior"])
    trusses, loose = "", ""
    if scode == 0:
        left = [g for g in srep["mesh"].get("left_out", []) if g["dim"] == 1]
        trusses = " ".join(g["group"] for g in left if g["group"] != "(none)")
        loose = "".join("; %d line elements in no physical group left out" % g["elements"] for g in left
                        if g["group"] == "(none)")
    if trusses:
        truss = '<section groups="%s" kind="truss" area="1e-4"/>' % trusses
        scode, sout, srep = run(dtmap, work, name + "_shell", geo, shell + "\n  " + truss, extra=["--posterior"])
    return "| `%s` | %s | %s | %s | %s%s |\n" % (model, "%.2g" % ratio if ratio == ratio else "", default, mem,
                                              shell_cell(scode, srep, sout, trusses), loose)


def write_table(table):
    with open(DOC) as f:
        text = f.read()
    start = text.index("| model | out of plane / size |", text.index(HEADING))
    end = text.index("\n\n", start) + 1
    while text[end:].startswith("Made by"):
        end = text.index("\n\n", end) + 1
    made = ("\nMade by `bench/surface_models.py build/dtmap --write` (gmsh-doc %s, Gmsh's defaults for the "
            "mesh).\n" % gmsh_doc_version())
    with open(DOC, "w") as f:
        f.write(text[:start] + table + made + text[end:])


def gmsh_doc_version():
    p = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "gmsh-doc"], stdout=subprocess.PIPE,
                       universal_newlines=True)
    return p.stdout.strip() or "unknown"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("models", nargs="*")
    ap.add_argument("--examples", default="/usr/share/doc/gmsh-doc/doc/gmsh")
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    dtmap = os.path.abspath(a.dtmap)
    work = tempfile.mkdtemp(prefix="dtmap-surfaces-")
    try:
        examples = uncompressed_copy(a.examples, work)
        models = a.models or sorted(os.path.relpath(p, examples) for p in glob.glob(
            os.path.join(examples, "tutorial", "*.geo")) + glob.glob(os.path.join(examples, "demos", "*", "*.geo")))
        if not a.models:
            models = [m for m in models if model_dim(os.path.join(examples, m)) == 2]
        table = HEADER + "".join(model_row(dtmap, work, examples, m) for m in models)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if a.write:
        write_table(table)
    sys.stdout.write(table)


if __name__ == "__main__":
    main()
