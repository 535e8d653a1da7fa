#!/usr/bin/python3
"""The share of the element bound at which CalculiX 2.20 runs each element
it builds from a 2D or 1D element (docs/deck.md, the caps of
src/deck/calculix.c). CalculiX expands S3 and M3D3 into C3D6 wedges, S4
into C3D8I incompatible-mode bricks, M3D4 into C3D8 bricks, B31 into C3D8I
bricks and CPS3/CPS4 into wedges and bricks with a free thickness strain
(gen3delem.f); the deck caps its step at a share of the element bound of
the extruded solids (dtmap's prism6/hex8 kernels, the `** layer` lines of
the deck's header give the smallest per part).

Each case is a mesh of one element type alone (triangles, quadrangles or
both; flat or curved; two thicknesses or sections), written by
`dtmap deck --solver calculix`, and run in the fixed-increment CalculiX
(bench/ccx_fixed_inc.sh) for --steps increments from a seeded random force
at every node (tests/common/deckutil.py). A run diverges when its largest
final displacement exceeds 1e3 x the one of the reference run at 0.2 x the
base, scaled by (dt / dt_ref)^2 (a free body under a constant force drifts
as t^2), or is not finite. The limit is bisected as a multiple of the base:
the smallest element bound of the layer's solids (S*, M3D*, B31), or the
deck's step (CPS*, which the deck scales, not caps).

Usage: /usr/bin/python3 bench/ccx_shell_caps.py DTMAP --ccx CCX_FIXED [--steps 400] [--bisect 7] [--only S4,B31]
       [--shape quad] [--what 't = 0.001 m']
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "common"))
import deckutil as du  # noqa: E402

H = 0.02  # mesh size, m

# Surfaces: a flat plate in an inclined plane (z = 0.3 x, so that the
# random force has three components), and a cylindrical panel (R 0.5 m,
# 40 degrees); each as two surfaces, so that "mixed" recombines one.
FLAT = """L = 0.16; W = 0.10;
Point(1) = {0, 0, 0}; Point(2) = {L/2, 0, 0.3*L/2}; Point(3) = {L, 0, 0.3*L};
Point(4) = {0, W, 0}; Point(5) = {L/2, W, 0.3*L/2}; Point(6) = {L, W, 0.3*L};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {4, 5}; Line(4) = {5, 6};
Line(5) = {1, 4}; Line(6) = {2, 5}; Line(7) = {3, 6};
Curve Loop(1) = {1, 6, -3, -5}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 7, -4, -6}; Plane Surface(2) = {2};
"""
CURVED = """R = 0.5; a = 20 * Pi / 180; W = 0.16;
Point(1) = {0, 0, 0}; Point(2) = {-R*Sin(a), 0, R*Cos(a)}; Point(3) = {0, 0, R}; Point(4) = {R*Sin(a), 0, R*Cos(a)};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4};
s1[] = Extrude {0, W, 0} { Curve{1}; }; s2[] = Extrude {0, W, 0} { Curve{2}; };
"""
STRAIGHT = """Point(1) = {0, 0, 0}; Point(2) = {0.3, 0, 0.09}; Line(1) = {1, 2};
"""
ARC = """R = 0.5; a = 20 * Pi / 180;
Point(1) = {0, 0, 0}; Point(2) = {-R*Sin(a), 0, R*Cos(a)}; Point(3) = {R*Sin(a), 0, R*Cos(a)};
Circle(1) = {2, 1, 3};
"""
PLANE = """Point(1) = {0, 0, 0}; Point(2) = {0.08, 0, 0}; Point(3) = {0.16, 0, 0};
Point(4) = {0, 0.1, 0}; Point(5) = {0.08, 0.1, 0}; Point(6) = {0.16, 0.1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {4, 5}; Line(4) = {5, 6};
Line(5) = {1, 4}; Line(6) = {2, 5}; Line(7) = {3, 6};
Curve Loop(1) = {1, 6, -3, -5}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 7, -4, -6}; Plane Surface(2) = {2};
"""


def surface_geo(base, shape):
    surfs = "{1, 2}" if base != CURVED else "{s1[1], s2[1]}"
    first = "1" if base != CURVED else "s1[1]"
    geo = base + 'Physical Surface("part") = %s;\n' % surfs
    if shape == "quad":
        geo += "Mesh.RecombineAll = 1;\n"
    elif shape == "mixed":
        geo += "Recombine Surface{%s};\n" % first
    return geo


def cases():
    out = []
    for elem, kind in (("S3", "shell"), ("S4", "shell"), ("M3D3", "membrane"), ("M3D4", "membrane")):
        shapes = ("tri",) if elem[-1] == "3" else ("quad", "mixed")
        for shape in shapes:
            for geom, base in (("flat", FLAT), ("curved", CURVED)):
                for t in (0.0002, 0.001, 0.004, 0.012):
                    out.append(dict(elem=elem, name="%s_%s_%s_t%g" % (elem, shape, geom, t), geo=surface_geo(base, shape),
                                    section='<section groups="part" kind="%s" thickness="%g"/>' % (kind, t),
                                    dim=2, form=None, what="t = %g m" % t, shape=shape, geom=geom))
    for geom, base in (("straight", STRAIGHT), ("curved", ARC)):
        for w, h in ((0.01, 0.03), (0.02, 0.02)):
            out.append(dict(elem="B31", name="B31_%s_%gx%g" % (geom, w, h), geo=base + 'Physical Curve("part") = {1};\n',
                            section='<section groups="part" kind="beam" width="%g" height="%g" orientation="0 1 0"/>'
                            % (w, h), dim=1, form=None, what="%g x %g m" % (w, h), shape="line", geom=geom))
    for shape, elem in (("tri", "CPS3"), ("quad", "CPS4")):
        for t in (0.001, 0.004, 0.012):
            out.append(dict(elem=elem, name="%s_t%g" % (elem, t), geo=surface_geo(PLANE, shape),
                            section='<section groups="part" kind="plane-stress" thickness="%g"/>' % t, dim=2,
                            form="plane-stress", what="t = %g m" % t, shape=shape, geom="flat"))
    return out


def deck(dtmap, case, tmp):
    d = os.path.join(tmp, case["name"])
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "g.geo"), "w") as f:
        f.write(case["geo"])
    form = ' formulation="%s"' % case["form"] if case["form"] else ""
    with open(os.path.join(d, "s.xml"), "w") as f:
        f.write('<dtmap-scene version="1">\n  <geometry file="g.geo"/>\n  <meshing size="%g" dim="%d"/>\n'
                '  <material name="steel" groups="part" E="200e9" nu="0.3" rho="7850"/>\n  %s\n'
                '  <effects><elastic%s/></effects>\n  <time safety="0.9"/>\n</dtmap-scene>\n'
                % (H, case["dim"], case["section"], form))
    out = os.path.join(d, "d.inp")
    subprocess.run([dtmap, "deck", os.path.join(d, "s.xml"), "--solver", "calculix", "-o", out, "-q"], check=True)
    text = open(out).read()
    types = dict((m.group(1), 0) for m in re.finditer(r"\*ELEMENT, TYPE=(\w+)", text))
    for t in types:
        block = text.split("*ELEMENT, TYPE=%s," % t)[1].split("\n*")[0]
        types[t] = len([x for x in block.split("\n")[1:] if x.strip()])
    bounds = [float(m.group(1)) for m in re.finditer(r"^\*\* layer \S+ \(\w+\): element bound of its solids (\S+) s",
                                                     text, re.M)]
    step = float(re.search(r"^\*\* step: (\S+) s", text, re.M).group(1))
    return out, types, (min(bounds) if bounds else step), ("bound" if bounds else "step"), step


def run(ccx, path, dt, steps):
    name, _ = du.prepare(path, steps * dt, increment=dt)
    code, log, u, est, sel = du.run(ccx, name, fixed=dt, timeout=3600)
    if code or sel is None or abs(sel / dt - 1) > 1e-6:
        sys.exit("ccx did not run at the fixed increment %g (exit %d):\n%s" % (dt, code, log[-1500:]))
    return u, est


def measure(a, case, tmp):
    path, types, base, basis, step = deck(a.dtmap, case, tmp)
    r0 = 0.2
    u0, est = run(a.ccx, path, r0 * base, a.steps)
    if not u0 < float("inf"):
        r0 = 0.05
        u0, est = run(a.ccx, path, r0 * base, a.steps)

    def bad(r):
        u, _ = run(a.ccx, path, r * base, a.steps)
        return not u < 1e3 * u0 * (r / r0) ** 2

    hi = 1.2
    while not bad(hi) and hi < 10:
        hi *= 1.5
    lo = r0
    for _ in range(a.bisect):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if bad(mid) else (mid, hi)
    return dict(types=types, base=base, basis=basis, step=step, lo=lo, hi=hi, est=est)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dtmap")
    ap.add_argument("--ccx", required=True)
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--bisect", type=int, default=7)
    ap.add_argument("--only", help="element names, comma-separated (S3, S4, M3D3, M3D4, B31, CPS3, CPS4)")
    ap.add_argument("--shape", help="only this mesh shape (tri, quad, mixed, line)")
    ap.add_argument("--what", help="only this thickness or section (as the table writes it: 't = 0.004 m')")
    a = ap.parse_args()
    a.dtmap, a.ccx = os.path.abspath(a.dtmap), os.path.abspath(a.ccx)
    tmp = tempfile.mkdtemp(prefix="dtmap-ccx-caps-")
    print("| element | mesh | shape | thickness / section | elements | base (s) | ccx's limit / base | "
          "ccx's own estimate / base |")
    print("|---|---|---|---|---|---|---|---|")
    for c in cases():
        if (a.only and c["elem"] not in a.only.split(",")) or (a.shape and c["shape"] != a.shape) or \
                (a.what and c["what"] != a.what):
            continue
        r = measure(a, c, tmp)
        print("| %s | %s | %s | %s | %s | %.5g (%s) | [%.4f, %.4f] | %.4f |" % (
            c["elem"], c["geom"], c["shape"], c["what"], " + ".join("%d %s" % (n, t) for t, n in r["types"].items()),
            r["base"], "element bound" if r["basis"] == "bound" else "deck's step", r["lo"], r["hi"],
            r["est"] / r["base"] if r["est"] else math.nan), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
