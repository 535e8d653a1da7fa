"""One unit rule for every figure (issue 43, docs/units.md): the same model
run in SI and in mm-t-s (<dtmap-scene units="mm-t-s">: mm, t, s, N, MPa,
t/mm^3) gives the same figures once converted, in the summary, the report,
the views and their .opt, and Python's result.

Models, each the same mesh in both systems (Gmsh meshes a geometry
differently at a scale 1000x apart, so a geometry meshed twice would not
compare figure by figure):
- a solid from STEP: a 60 x 40 x 20 mm block with a 2 mm slot, written as a
  STEP in mm by Gmsh; the mm-t-s scene meshes the STEP, the SI scene reads
  that mesh with <mesh unit="mm">; a target no mesh reaches gives mass
  scaling, shape- and thickness-limited elements, features and remedies;
  verify --accuracy on that mesh gives its wave line and report;
- a shell panel: /work/shared/cases' curved quad/tri panel (8 mm shell) with
  a 10 x 30 mm ring beam, a .msh in metres (<mesh unit="m"> in mm-t-s);
- a refine with point masses: a block with a 0.6 mm flange, extruded (the
  same hexahedra at any scale), refined with --keep-counts and
  --max-added-mass so that point masses meet the target;
- a 2D plane-stress plate without a section, whose masses are per unit
  thickness (kg/m against t/mm, 1e6 apart);
- Python's dtmap.analyse on the flange in both systems.

Every number of a summary line is parsed with the unit printed after it:
a length, area, mass, density, modulus or speed must be printed in the
system's unit (m and mm, kg and t, ...) and agree after conversion; a
number without a unit, or with the same unit in both, must be the same
number. Tolerance: one unit in the last digit printed (the two systems
round the same value differently in its last digit). Lines and report
fields are paired by their words; wall times are left out. The report is
in SI in both (its top-level "units" says so), but for its "model" object,
in the scene's units; its fields agree to 1e-6 relative (the same mesh
computed in two systems: the steps agree to about 1e-12, t380). The views
agree to 1e-9 relative once converted by the unit their .opt Format names.
A run in mm-t-s that cannot be compared (refine's remeshes) is checked
for figures printed in m or kg."""

import math
import os
import re
import shutil
import subprocess
import sys

import testutil as tu

CASES = "/work/shared/cases"
PANEL = os.path.join(CASES, "panel_quad_shell_beam.msh")

# SI unit -> (mm-t-s unit, value in mm-t-s of one SI unit)
CONVERT = {"m": ("mm", 1e3), "m^2": ("mm^2", 1e6), "m^4": ("mm^4", 1e12), "kg": ("t", 1e-3),
           "kg/m^3": ("t/mm^3", 1e-12), "m/s": ("mm/s", 1e3), "Pa": ("MPa", 1e-6), "N/m": ("N/mm", 1e-3),
           "kg/m": ("t/mm", 1e-6)}
TO_SI = {mm: si for si, (mm, _) in CONVERT.items()}
UNIT = r"(mm\^2|m\^2|mm\^4|m\^4|t/mm\^3|kg/m\^3|mm/s|m/s|MPa|Pa|N/mm|N/m|t/mm|kg/m|mm|m|kg|t|s|h|Hz|ns|%|x)"
NUM = r"(?<![\w.^])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?"
FIGURE = re.compile(r"(%s)(?: ?%s(?![\w^/]))?" % (NUM, UNIT))
TUPLE = re.compile(r"\(((?:\s*%s\s*,)+\s*%s\s*)\) %s(?![\w^/])" % (NUM, NUM, UNIT))
# Report fields that are no figure of the model: paths, wall times, the units
# (checked apart), how the mesh was made (Gmsh in one system, read in the
# other), and Gmsh tags, which ties between equal values may swap.
SKIP_FIELDS = ("scene", "timings", "seconds", "units", "import", "file", "algorithm", "threads", "reproducible",
               "node", "nodal_node", "element", "worst_element", "physical_element", "own_element", "binding_element",
               "worst_alone_element",
               # measured wall times of the selective mass's products (refine --selective-mass) and what
               # follows from them: not reproducible from one run to the next
               "product_ratio", "runtime_factor", "runtime_ratio", "mesh_and_selective_mass/cost_ratio")
SKIP = ("dtmap 0.", "wrote ", "units        ", "import       ", "real", "user", "sys", "  mesh + selective mass: round",
        "  time per step ", "  run time        x")


def figures(line, length_unit=None):
    """(skeleton, [(value, unit, digits)]) of a summary line: each number
    with the unit printed after it (a tuple's unit after its parenthesis),
    the skeleton the line with each figure replaced by '#' and its unit in
    SI (so that an SI line and an mm-t-s line of the same figures have the
    same skeleton)."""
    line = TUPLE.sub(lambda m: "(" + ", ".join("%s %s" % (x.strip(), m.group(2)) for x in m.group(1).split(",")) + ")",
                     line)
    out = []

    def one(m):
        text, unit = m.group(1), m.group(2) or ""
        digits = len(re.sub(r"[eE].*|[-+.]|^[-+0.]*", "", text)) or 1
        out.append((float(text), unit, digits))
        return "#" + (" " + TO_SI.get(unit, unit) if unit else "")
    return re.sub(r"\s+", " ", FIGURE.sub(one, line)).strip(), out


def summary_lines(log):
    """The comparable lines of a summary: no header, file names, unit or
    import line (those differ by design), wall times replaced; the rows of
    the smallest-steps table as rank, step and length with the header's
    unit; refine's rounds without their time column."""
    lines, length_unit = [], None
    for line in log.splitlines():
        if "<section " in line:  # a proposed section's attributes are lengths in the scene's unit, the line's own
            unit = re.findall(r"\d (mm|m)\b", line)
            if unit:
                line = re.sub(r'(thickness|width|height)="(%s)"' % NUM, r'\1="\2 %s"' % unit[-1], line)
        if not line.strip() or line.startswith(SKIP):
            length_unit = None if not line.strip() else length_unit
            continue
        head = re.search(r"length \((\w+)\)", line)
        if head:
            length_unit = head.group(1)
            line = line.replace(head.group(0), "length (%s)" % TO_SI.get(length_unit, length_unit))
        elif length_unit and re.match(r"\s+\d+\s+\d+ \w+", line):
            f = line.split()  # rank, element, type, group, dt, length, effect (ties may swap elements)
            line = "  row %s dt %s s length %s %s %s" % (f[0], f[4], f[5], length_unit, f[6])
        elif re.match(r"\s+\d+ (nodal|elem\.|global) ", line):
            f = line.split()
            f[11] = "T"  # the round's wall time
            line = " ".join(f)
        lines.append(line)
    return lines


class Compare:
    """Pairs the lines (or texts) of an SI and an mm-t-s output by their
    skeletons and collects every figure that does not agree."""

    def __init__(self, what):
        self.what, self.bad, self.model_mass = what, [], 1e-3

    def value(self, where, si, mm):
        (a, ua, da), (b, ub, db) = si, mm
        if ua in CONVERT:
            want_unit, f = CONVERT[ua]
            if ub != want_unit:
                return self.bad.append("%s: %g %s in SI is printed %g %s in mm-t-s (want %s)" % (where, a, ua, b, ub,
                                                                                                  want_unit))
            a *= f
        elif ub in TO_SI or ua != ub:
            return self.bad.append("%s: %g %s against %g %s" % (where, a, ua, b, ub))
        tol = 10.0 ** (1 - min(da, db)) * max(abs(a), abs(b))
        if not (abs(a - b) <= tol or a == b):
            self.bad.append("%s: %g %s in SI is %g %s in mm-t-s: %s" % (where, si[0], ua, b, ub,
                                                                        "no unit" if not ua else "not converted"))

    def lines(self, si_lines, mm_lines):
        pool = {}
        for line in mm_lines:
            pool.setdefault(figures(line)[0], []).append(line)
        for line in si_lines:
            skel, fs = figures(line)
            if not pool.get(skel):
                self.bad.append("%s: no mm-t-s line reads like the SI line %r" % (self.what, line))
                continue
            other = pool[skel].pop(0)
            for a, b in zip(fs, figures(other)[1]):
                self.value("%s %r / %r" % (self.what, line, other), a, b)
        left = [x for v in pool.values() for x in v]
        if left:
            self.bad.append("%s: mm-t-s lines with no SI line: %r" % (self.what, left))

    def json(self, where, si, mm, model=False):
        """Report fields: numbers the same (SI in both) but in "model" (the
        scene's units: mass x 1e-3 and lengths x 1e3 in mm-t-s)."""
        if isinstance(si, dict):
            def kept(k):
                return k not in SKIP_FIELDS and where.split("/")[-1] + "/" + k not in SKIP_FIELDS

            keys = sorted(k for k in si if kept(k))
            if keys != sorted(k for k in mm if kept(k)):
                return self.bad.append("%s: fields %s against %s" % (where, sorted(si), sorted(mm)))
            for k in keys:
                self.json(where + "/" + k, si[k], mm[k], model or where + "/" + k == "/model")
        elif isinstance(si, list):
            if len(si) != len(mm):
                return self.bad.append("%s: %d items against %d" % (where, len(si), len(mm)))
            if where.endswith("/worst"):  # ties at the same step may list other elements: rank by rank
                si = [{"dt": x["dt"], "length": x["length"]} for x in si]
                mm = [{"dt": x["dt"], "length": x["length"]} for x in mm]
            if si and all(isinstance(x, dict) and "group" in x for x in si + mm):  # ties may order groups otherwise
                si, mm = sorted(si, key=lambda x: x["group"]), sorted(mm, key=lambda x: x["group"])
            for i, (a, b) in enumerate(zip(si, mm)):
                self.json("%s[%d]" % (where, i), a, b, model)
        elif isinstance(si, str):
            if si != mm:
                self.lines([si], [mm]) if figures(si)[0] == figures(mm)[0] else self.bad.append(
                    "%s: %r against %r" % (where, si, mm))
        elif isinstance(si, (int, float)) and not isinstance(si, bool):
            f = 1.0
            if model and re.search(r"mass", where):
                f = self.model_mass
            elif model and re.search(r"bbox", where):
                f = 1e3
            a, b = si * f, mm
            if not (abs(a - b) <= 1e-6 * max(abs(a), abs(b)) + 1e-15 * f or a == b):
                self.bad.append("%s: %r in SI is %r in mm-t-s (want %r)" % (where, si, mm, a))
        elif si != mm:
            self.bad.append("%s: %r against %r" % (where, si, mm))


def view_data(path):
    """[(name, format, {tag: values})] of the views of the .msh at path, its
    .opt merged (Gmsh merges X.msh.opt when it opens X.msh)."""
    script = """
import gmsh, json, sys, math
gmsh.initialize(["v", "-v", "0"])
gmsh.open(sys.argv[1])
out = []
for i, tag in enumerate(gmsh.view.getTags()):
    name = gmsh.option.getString("View[%d].Name" % i)
    fmt = gmsh.option.getString("View[%d].Format" % i)
    kind, tags, data, _, _ = gmsh.view.getModelData(tag, 0)
    out.append([name, fmt, {str(t): [x if math.isfinite(x) else str(x) for x in d] for t, d in zip(tags, data)}])
print(json.dumps(out))
gmsh.finalize()
"""
    import json
    p = subprocess.run([sys.executable, "-c", script, path], stdout=subprocess.PIPE, universal_newlines=True,
                       env=tu.plain_env())
    return json.loads(p.stdout.splitlines()[-1])


def compare_views(c, si_path, mm_path):
    si, mm = view_data(si_path), view_data(mm_path)
    if [v[0] for v in si] != [v[0] for v in mm]:
        return c.bad.append("views %s against %s" % ([v[0] for v in si], [v[0] for v in mm]))
    for (name, fa, da), (_, fb, db) in zip(si, mm):
        ua, ub = fa.replace("%.3g", "").strip(), fb.replace("%.3g", "").strip()
        f = 1.0
        if ua in CONVERT:
            f = CONVERT[ua][1]
            if ub != CONVERT[ua][0]:
                c.bad.append("view '%s': Format %r in SI, %r in mm-t-s" % (name, fa, fb))
        elif ua != ub:
            c.bad.append("view '%s': Format %r in SI, %r in mm-t-s" % (name, fa, fb))
        if name.startswith("smallest"):  # the elements at the 1 % quantile: ties may take others in
            da, db = {"min": [min(v[0] for v in da.values())]}, {"min": [min(v[0] for v in db.values())]}
        if sorted(da) != sorted(db):
            c.bad.append("view '%s': other tags" % name)
            continue
        worst = 0.0
        for t, va in da.items():
            for a, b in zip(va, db[t]):
                if isinstance(a, str) or isinstance(b, str):
                    worst = worst if a == b else math.inf
                else:
                    worst = max(worst, abs(a * f - b) / max(abs(a * f), abs(b), 1e-300))
        if worst > 1e-9:
            c.bad.append("view '%s' (Format %r in SI, %r in mm-t-s): values differ by %.3g relative once converted"
                         % (name, fa, fb, worst))


# The ratio SI / mm-t-s of each number of a deck's data line, by card (a
# length 1e-3, a modulus 1e6, a density 1e12, a mass 1e3; ids, counts,
# Poisson's ratio and steps 1): the decks of one mesh in the two systems.
DECK_FACTORS = {"*NODE": lambda n: [1] + [1e-3] * (n - 1), "*ELASTIC": lambda n: [1e6, 1][:n],
                "*DENSITY": lambda n: [1e12], "*MASS": lambda n: [1e3] * n,
                "*MAT_ELASTIC_TITLE": lambda n: [1, 1e12, 1e6, 1][:n], "*ELEMENT_MASS": lambda n: [1, 1, 1e3, 1][:n]}
NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")


def deck_parts(text, comment):
    """(header lines without the comment mark, [(card, [numbers])] of the data lines)."""
    head, data, card = [], [], ""
    for line in text.splitlines():
        if line.startswith(comment):
            if not line.startswith("$#"):
                head.append(line[len(comment):].strip())
        elif line.startswith("*"):
            card = line.split(",")[0].strip().upper()
        else:
            toks = [t for t in re.split(r"[,\s]+", line.strip()) if t]
            nums = [float(t) for t in toks if NUMBER.match(t)]
            if nums:
                data.append((card, nums))
    return head, data


def compare_decks(c, solver, si, mm):
    comment = "$" if solver == "lsdyna" else "**"
    (hs, ds), (hm, dm) = deck_parts(si, comment), deck_parts(mm, comment)
    skip = ("dtmap ", "scene:", "units:")
    c.what = solver + " deck header"
    c.lines([h for h in hs if not h.startswith(skip)], [h for h in hm if not h.startswith(skip)])
    for h, want in ((hs, "units: SI (lengths m, masses kg"), (hm, "units: mm-t-s (lengths mm, masses t")):
        if not any(x.startswith(want) for x in h):
            c.bad.append("%s deck: no header line %r" % (solver, want))
    if len(ds) != len(dm):
        return c.bad.append("%s deck: %d data lines in SI, %d in mm-t-s" % (solver, len(ds), len(dm)))
    for k, ((card, a), (card_m, b)) in enumerate(zip(ds, dm)):
        f = DECK_FACTORS.get(card, lambda n: [1] * n)(len(a))
        if card != card_m or len(a) != len(b) or len(f) != len(a):
            c.bad.append("%s deck line %d: %s %r against %s %r" % (solver, k, card, a, card_m, b))
            continue
        for x, y, g in zip(a, b, f):
            if abs(x - y * g) > 1e-9 * max(abs(x), abs(y * g)):
                c.bad.append("%s deck %s: %r in SI, %r in mm-t-s (want %r)" % (solver, card, x, y, y * g))


def scene(name, source, units, extra=""):
    mm = units == "mm"
    mat = 'E="%s" nu="0.3" rho="%s"' % (("210000", "7.85e-9") if mm else ("210e9", "7850"))
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1"%s>
  %s
  <material name="steel" %s default="true"/>
  %s
  <effects><elastic/></effects>
  <time safety="0.9" duration="1e-4"%s/>
</dtmap-scene>
""" % (' units="mm-t-s"' if mm else "", source, mat, extra[0] if extra else "", extra[1] if extra else ""))


def run(name, *args):
    code, log = tu.run("run", name + ".xml", "-o", name + "_dt.msh", "--report", name + ".json", *args)
    assert code == 0, log
    return log, tu.report(name + ".json")


class Units(tu.unittest.TestCase):
    def check(self, si, mm, what, views=True, log_si=None, log_mm=None, report_si=None, report_mm=None,
              model_mass=1e-3):
        c = Compare(what)
        c.model_mass = model_mass  # t in kg (t/mm in kg/m in 2D without a section)
        c.lines(summary_lines(log_si), summary_lines(log_mm))
        c.json("", report_si, report_mm)
        for r, want in ((report_si, {"system": "SI", "report": "SI", "model": "SI"}),
                        (report_mm, {"system": "mm-t-s", "report": "SI", "model": "mm-t-s"})):
            if r.get("units") != want:
                c.bad.append("report units %r, not %r" % (r.get("units"), want))
        if views:
            compare_views(c, tu.path(si), tu.path(mm))
        self.assertEqual(c.bad, [], "\n".join(c.bad[:40]))

    def test_solid_from_step(self):
        """A STEP block with a slot: thickness-limited layers, features,
        remedies, mass scaling, the smallest steps, the views."""
        import gmsh
        gmsh.initialize(["t381", "-v", "0"])
        gmsh.model.occ.addBox(0, 0, 0, 60, 40, 20, 1)
        gmsh.model.occ.addBox(20, -1, 2, 10, 42, 20, 2)
        gmsh.model.occ.cut([(3, 1)], [(3, 2)])
        gmsh.model.occ.synchronize()
        gmsh.write(tu.path("slot.step"))
        gmsh.finalize()
        time = ("", ' target="1.2e-6"')
        scene("slot_mm", '<geometry file="%s"/>\n  <meshing size="6"/>' % tu.path("slot.step"), "mm", time)
        log_mm, r_mm = run("slot_mm")
        self.assertIn("import       unit mm found in the file", log_mm)
        scene("slot_si", '<mesh file="%s" unit="mm"/>' % tu.path("slot_mm_dt.msh"), "si", time)
        log_si, r_si = run("slot_si")
        self.assertIn("thickness    ", log_mm)
        self.assertIn("model curve", log_mm)
        self.check("slot_si_dt.msh", "slot_mm_dt.msh", "STEP slot", log_si=log_si, log_mm=log_mm, report_si=r_si,
                   report_mm=r_mm)
        # verify --accuracy on the same mesh: its wave line and its report (speed, wavelength, window in SI)
        scene("slot_vmm", '<mesh file="%s"/>' % tu.path("slot_mm_dt.msh"), "mm")
        scene("slot_vsi", '<mesh file="%s" unit="mm"/>' % tu.path("slot_mm_dt.msh"), "si")
        out = {}
        for u in ("vsi", "vmm"):
            code, log = tu.run("verify", "slot_%s.xml" % u, "--accuracy", "--periods", "2", "--report",
                               "slot_%s.json" % u)
            self.assertIn(code, (0, 1), log)  # 1: the measured error disagrees with the prediction (a coarse mesh)
            out[u] = ([x for x in log.splitlines() if "host material" in x], tu.report("slot_%s.json" % u))
        c = Compare("verify")
        c.lines(out["vsi"][0], out["vmm"][0])
        c.json("", out["vsi"][1], out["vmm"][1])
        self.assertEqual(out["vmm"][1]["units"], {"system": "mm-t-s", "report": "SI", "model": "mm-t-s"})
        self.assertEqual(c.bad, [])

    def test_shell_panel(self):
        """Shell and beam sections: thickness, area, the sections' lines."""
        if not os.path.exists(PANEL):
            self.skipTest(PANEL + " is not here")
        sections = {"si": ('<section groups="skin" kind="shell" thickness="0.008"/>\n  <section groups="stiffener" '
                           'kind="beam" width="0.01" height="0.03" orientation="1 0 0"/>'),
                    "mm": ('<section groups="skin" kind="shell" thickness="8"/>\n  <section groups="stiffener" '
                           'kind="beam" width="10" height="30" orientation="1 0 0"/>')}
        for u in ("si", "mm"):
            shutil.copy(PANEL, tu.path("panel.msh"))
            scene("panel_" + u, '<mesh file="%s"%s/>' % (tu.path("panel.msh"), ' unit="m"' if u == "mm" else ""), u,
                  (sections[u], ' target="2e-6"'))
        log_si, r_si = run("panel_si")
        log_mm, r_mm = run("panel_mm")
        self.assertIn("shell, t 8 mm", log_mm)
        self.check("panel_si_dt.msh", "panel_mm_dt.msh", "shell panel", log_si=log_si, log_mm=log_mm, report_si=r_si,
                   report_mm=r_mm)

    def test_plane_2d(self):
        """A plane-stress plate (2D, no section): its masses are per unit
        thickness, kg/m in SI and t/mm in mm-t-s (1e6 apart, not 1e3)."""
        import gmsh
        gmsh.initialize(["t381", "-v", "0"])
        gmsh.model.occ.addRectangle(0, 0, 0, 20, 10)  # mm
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 2.5)  # unstructured: no two smallest steps tie
        gmsh.model.addPhysicalGroup(2, [1], 1)
        gmsh.model.setPhysicalName(2, 1, "plate")
        gmsh.model.mesh.generate(2)
        gmsh.write(tu.path("plate.msh"))
        gmsh.finalize()
        for u in ("si", "mm"):
            scene("plate_" + u, '<mesh file="%s"%s/>' % (tu.path("plate.msh"), ' unit="mm"' if u == "si" else ""), u,
                  ("", ' target="1e-6"'))
            with open(tu.path("plate_%s.xml" % u)) as f:
                text = f.read().replace("<elastic/>", '<elastic formulation="plane-stress"/>')
            tu.write("plate_%s.xml" % u, text)
        log_si, r_si = run("plate_si")
        log_mm, r_mm = run("plate_mm")
        self.assertIn("t/mm (per unit thickness)", log_mm)
        self.assertAlmostEqual(r_mm["mass_scaling"]["total_mass"], 7850 * 2e-4, delta=1e-12)  # rho A, kg/m
        self.check("plate_si_dt.msh", "plate_mm_dt.msh", "2D plate", log_si=log_si, log_mm=log_mm, report_si=r_si,
                   report_mm=r_mm, model_mass=1e-6)

    def flange(self, u):
        s = "1" if u == "mm" else "0.001"
        tu.write("flange_%s.geo" % u, """s = %s;
Point(1) = {0, 0, 0}; Point(2) = {20*s, 0, 0}; Point(3) = {40*s, 0, 0};
Point(4) = {0, 20*s, 0}; Point(5) = {20*s, 20*s, 0}; Point(6) = {40*s, 20*s, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {4, 5}; Line(4) = {5, 6};
Line(5) = {1, 4}; Line(6) = {2, 5}; Line(7) = {3, 6};
Curve Loop(1) = {1, 6, -3, -5}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 7, -4, -6}; Plane Surface(2) = {2};
Transfinite Curve{1:7} = 6;
Transfinite Surface{1, 2}; Recombine Surface{1, 2};
a[] = Extrude {0, 0, 0.6*s} { Surface{1}; Layers{1}; Recombine; };
b[] = Extrude {0, 0, 0.6*s} { Surface{2}; Layers{1}; Recombine; };
c[] = Extrude {0, 0, 9.4*s} { Surface{a[0]}; Layers{3}; Recombine; };
Physical Volume("block") = {a[1], c[1]};
Physical Volume("flange") = {b[1]};
""" % s)
        return scene("flange_" + u, '<geometry file="%s"/>\n  <meshing dim="3"/>' % tu.path("flange_%s.geo" % u), u)

    def test_refine_with_point_masses(self):
        """The 0.6 mm flange (issue 43's '0.6047 m thin'), refined with point
        masses: refine's table, its met line, the point masses, the views
        (added mass at nodes) and the report's rounds; with --selective-mass,
        the way mesh + selective mass beside them (its masses in the
        scene's unit in the summary, in SI in the report)."""
        out = {}
        for u in ("si", "mm"):
            self.flange(u)
            code, log = tu.run("refine", "flange_%s.xml" % u, "--target", "1.5e-7", "--keep-counts",
                               "--max-added-mass", "20", "--selective-mass", "-o", "flange_%s_r.msh" % u, "--report", "flange_%s_r.json" % u)
            self.assertEqual(code, 0, log)
            out[u] = (log, tu.report("flange_%s_r.json" % u))
        self.assertIn("point masses", out["mm"][0])
        self.assertIn("added mass at 96 nodes", out["mm"][0])
        self.check("flange_si_r.msh", "flange_mm_r.msh", "refine", log_si=out["si"][0], log_mm=out["mm"][0],
                   report_si=out["si"][1], report_mm=out["mm"][1])
        # the thickness line of run on the same flange: 0.6 mm, not 0.6 m
        log_si, r_si = run("flange_si")
        log_mm, r_mm = run("flange_mm")
        self.assertRegex(log_mm, r"'flange' is 0\.6 mm thin")
        self.check("flange_si_dt.msh", "flange_mm_dt.msh", "flange run", log_si=log_si, log_mm=log_mm,
                   report_si=r_si, report_mm=r_mm)

    def test_decks(self):
        """The three decks of one mesh (a 60 x 40 x 20 mm block; a target that needs mass: CalculiX's and
        Abaqus's point masses, LS-DYNA's DT2MS prediction) written in SI and in mm-t-s: every header line's
        figures agree with their units, each header states its system, and every number of the data
        lines is the other's in its own unit (nodes, E, rho, masses; ids and steps the same)."""
        import gmsh
        gmsh.initialize(["t381", "-v", "0"])
        gmsh.model.occ.addBox(0, 0, 0, 60, 40, 20)
        gmsh.model.occ.synchronize()
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 8)
        gmsh.model.mesh.generate(3)
        gmsh.write(tu.path("deckblock.msh"))
        gmsh.finalize()
        scene("deck_mm", '<mesh file="%s"/>' % tu.path("deckblock.msh"), "mm")
        scene("deck_si", '<mesh file="%s" unit="mm"/>' % tu.path("deckblock.msh"), "si")
        c = Compare("decks")
        for solver in ("calculix", "abaqus", "lsdyna"):
            text = {}
            for u in ("si", "mm"):
                out = "deck_%s_%s.inp" % (u, solver)
                code, log = tu.run("deck", "deck_%s.xml" % u, "--solver", solver, "-o", out, "-q", "--target",
                                   "4e-7", "--max-added-mass", "50")
                self.assertEqual(code, 0, log)
                with open(tu.path(out)) as f:
                    text[u] = f.read().replace("deck_%s_" % u, "deck_")  # the include slots are named after it
            self.assertRegex(text["mm"], r"added mass: [\d.e+-]+ t at|by its rule [\d.e+-]+ t at")
            compare_decks(c, solver, text["si"], text["mm"])
        self.assertEqual(c.bad, [], "\n".join(c.bad[:40]))

    def test_no_metres_in_mm_t_s(self):
        """refine's remeshes, sweep and deck in mm-t-s (uniform sizes,
        causes, the sweep's table and CSV, the deck's added mass): no figure
        is printed in m or kg (Gmsh meshes them otherwise than in SI, so
        they are checked for their units only). The deck file itself is not
        checked here (its header is issue 43's LS-DYNA work)."""
        scene("box_mm", '<geometry file="%s"/>\n  <meshing size="4"/>' % os.path.join(tu.SRC, "tests", "data", "units",
                                                                                      "part_mm.step"), "mm")
        code, log = tu.run("refine", "box_mm.xml", "--target", "5e-7", "-o", "fr.msh", "--report", "fr.json")
        self.assertIn(code, (0, 1), log)
        self.assertRegex(log, r"uniform [\d.e+-]+ mm")
        # sweep: its table, its cheapest size, its CSV header; deck: its summary lines (not the deck's header)
        code, sweep = tu.run("sweep", "box_mm.xml", "--sizes", "8,5", "--csv", "sw.csv")
        self.assertEqual(code, 0, sweep)
        self.assertRegex(sweep, r"\(mm\)\s+\(s\)")
        with open(tu.path("sw.csv")) as f:
            self.assertTrue(f.readline().startswith("h_mm,"))
        code, deck = tu.run("deck", "box_mm.xml", "--solver", "calculix", "-o", "d.inp", "--target", "3e-7",
                            "--max-added-mass", "60", "--report", "d.json")
        self.assertEqual(code, 0, deck)
        self.assertRegex(deck, r"added mass [\d.e+-]+ t at \d+ nodes")
        d = tu.report("d.json")
        self.assertAlmostEqual(d["deck"]["added_mass"] / d["deck"]["model_mass"] * d["model"]["mass"] * 1e3,
                               d["deck"]["added_mass"], delta=1e-9 * d["deck"]["added_mass"])  # kg in the report
        wrong = [line for text in (log, sweep, deck) for line in text.splitlines()
                 for v, u, _ in figures(line)[1] if u in CONVERT]
        self.assertEqual(wrong, [])

    def test_python_result(self):
        """dtmap.analyse on the same flange mesh in both systems: its units,
        its lengths and size suggestion in the scene's length unit, the
        same steps. (Not under the sanitizers: this script does not load
        libdtmap itself, so its child would run without their runtimes;
        t901 drives the module there.)"""
        if tu.SANITIZED:
            self.skipTest("the Python module under the sanitizers is t901's")
        code = """
import dtmap, gmsh, json, sys
out = {}
for u in ("si", "mm"):
    gmsh.initialize(["py", "-v", "0"])
    gmsh.open(sys.argv[1] + "/flange_%s.geo" % u)
    gmsh.model.mesh.generate(3)
    r = dtmap.analyse(scene=sys.argv[1] + "/flange_%s.xml" % u, views=False)
    out[u] = {"units": r.units, "length": r.length.tolist(), "dt": r.dt.tolist(), "rec": r.recommended}
    r.close()
    gmsh.finalize()
print(json.dumps(out))
"""
        self.flange("si"), self.flange("mm")
        env = dict(os.environ)
        p = subprocess.run([sys.executable, "-c", code, tu.tmpdir()], stdout=subprocess.PIPE, universal_newlines=True,
                           env=env)
        self.assertEqual(p.returncode, 0)
        import json
        out = json.loads(p.stdout.splitlines()[-1])
        self.assertEqual(out["mm"]["units"], {"system": "mm-t-s", "length": "mm", "area": "mm^2", "mass": "t",
                                              "density": "t/mm^3", "speed": "mm/s", "modulus": "MPa"})
        self.assertEqual(out["si"]["units"]["length"], "m")
        for a, b in zip(out["si"]["length"], out["mm"]["length"]):
            self.assertAlmostEqual(b / (1e3 * a), 1.0, delta=1e-9)
        self.assertAlmostEqual(out["mm"]["rec"] / out["si"]["rec"], 1.0, delta=1e-9)


if __name__ == "__main__":
    tu.main()
