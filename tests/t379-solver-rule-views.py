"""`dtmap run --solver-rule lsdyna,abaqus,calculix`: one ElementData view per
solver, "dt lsdyna", "dt abaqus", "dt calculix", each element's step by that
solver's own rule (src/deck/rules.c, the rule a deck's header estimates
with), and a summary line per solver with its smallest step, the element
and its centroid.

- The deck's header and the view agree: for every solver, on the bundled
  plate with a hole (plane stress triangles) and reinforced block
  (tetrahedra, trusses, a membrane), the smallest value of the view is the
  estimate the header of `dtmap deck --solver S` gives (10 significant
  digits there: within 1e-9 relative), on the same element; the summary
  prints the same digits, element and the element's centroid (the mean of
  its corners, from the mesh; 6 digits printed: within 1e-6 of the plate's
  size).
- Independently of dtmap's code, LS-DYNA's shell and 2D-solid rule on the
  plate's triangles: L_s / c with L_s = 2 A / (longest side) and the plate
  speed c = sqrt(E / (rho (1 - nu^2))) (aluminium, the scene's values),
  computed here from the nodes of the .msh (ASCII, 16 digits: within 1e-12
  relative); Abaqus's rule is dtmap's own elastic element step: the view is
  "dt elastic" exactly.
- CalculiX's rule covers no truss (it makes springs of them): the view
  leaves the trusses out.
- Bad lists are usage errors (exit 2) and nothing is written.
"""

import math
import os
import re
import shutil
import unittest

import gmsh

import testutil as tu

SOLVERS = ("lsdyna", "abaqus", "calculix")


def copy_scene(name):
    for ext in (".geo", ".xml"):
        shutil.copy(os.path.join(tu.SRC, "geometries", name + ext), tu.tmpdir())


def mesh_data(msh):
    """{view name: {tag: value}}, {element tag: (type, node tags)}, {node tag: xyz} of msh."""
    gmsh.initialize(["t379", "-v", "0"])
    try:
        gmsh.open(msh)
        views = {}
        for tag in gmsh.view.getTags():
            name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(tag))
            kind, tags, data, _, _ = gmsh.view.getModelData(tag, 0)
            if kind == "ElementData":
                views[name] = {int(t): float(d[0]) for t, d in zip(tags, data)}
        elements = {}
        types, etags, enodes = gmsh.model.mesh.getElements()
        for t, et, en in zip(types, etags, enodes):
            per = len(en) // len(et)
            for k, e in enumerate(et):
                elements[int(e)] = (int(t), [int(n) for n in en[k * per:(k + 1) * per]])
        ntags, xyz, _ = gmsh.model.mesh.getNodes()
        nodes = {int(n): xyz[3 * k:3 * k + 3] for k, n in enumerate(ntags)}
        return views, elements, nodes
    finally:
        gmsh.finalize()


def corners(etype):
    return {1: 2, 2: 3, 3: 4, 4: 4, 5: 8}[etype]


def run_with_rules(name, out):
    code, log = tu.run("run", name + ".xml", "-o", out, "--solver-rule", ",".join(SOLVERS))
    assert code == 0, log
    return log


def deck_estimate(name, solver):
    """(estimate, element) from the header of `dtmap deck NAME.xml --solver SOLVER`."""
    deck = "%s_%s.deck" % (name, solver)
    code, log = tu.run("deck", name + ".xml", "--solver", solver, "-o", deck, "-q")
    assert code == 0, log
    with open(tu.path(deck)) as f:
        m = re.search(r"own estimate for this mesh: (\S+) s \(element (\d+);", f.read())
    assert m, deck
    return float(m.group(1)), int(m.group(2))


def summary_lines(log):
    """{solver: (smallest, element, centroid)} from the summary."""
    out = {}
    for m in re.finditer(r"^  (\w+) +smallest (\S+) s \(.*\): element (\d+) at \((\S+), (\S+), (\S+)\) m$",
                         log, re.M):
        out[m.group(1)] = (float(m.group(2)), int(m.group(3)), [float(m.group(k)) for k in (4, 5, 6)])
    return out


class SolverRule(unittest.TestCase):
    def check_against_decks(self, name):
        """Each solver's view minimum is its deck's estimate, on the same element; the summary agrees."""
        copy_scene(name)
        log = run_with_rules(name, name + "_r.msh")
        views, elements, nodes = mesh_data(tu.path(name + "_r.msh"))
        lines = summary_lines(log)
        size = max(max(abs(x) for x in xyz) for xyz in nodes.values())
        for solver in SOLVERS:
            view = views["dt " + solver]
            tag = min(view, key=view.get)
            est, element = deck_estimate(name, solver)
            self.assertLessEqual(abs(view[tag] - est), 1e-9 * est, (name, solver, view[tag], est))
            self.assertEqual(tag, element, (name, solver))
            smallest, sel, centroid = lines[solver]
            self.assertLessEqual(abs(smallest - view[tag]), 1e-9 * est, (name, solver))
            self.assertEqual(sel, tag)
            etype, enodes = elements[tag]
            for d in range(3):
                c = sum(nodes[n][d] for n in enodes[:corners(etype)]) / corners(etype)
                self.assertLessEqual(abs(centroid[d] - c), 1e-6 * size, (name, solver, d))
        return views, elements, nodes

    def test_plate(self):
        views, elements, nodes = self.check_against_decks("plate_with_hole")
        E, nu, rho = 70e9, 0.33, 2700.0
        c = math.sqrt(E / (rho * (1 - nu * nu)))
        lsdyna = views["dt lsdyna"]
        self.assertEqual(len(lsdyna), len(views["dt"]))
        for tag, value in lsdyna.items():
            etype, enodes = elements[tag]
            self.assertEqual(etype, 2)  # 3-node triangles
            p = [nodes[n] for n in enodes]
            u = [p[1][k] - p[0][k] for k in range(3)]
            v = [p[2][k] - p[0][k] for k in range(3)]
            area = 0.5 * abs(u[0] * v[1] - u[1] * v[0])
            longest = max(math.dist(p[i], p[(i + 1) % 3]) for i in range(3))
            expect = 2 * area / longest / c
            self.assertLessEqual(abs(value - expect), 1e-12 * expect, tag)
        self.assertEqual(views["dt abaqus"], views["dt elastic"])

    def test_reinforced_block(self):
        views, elements, _ = self.check_against_decks("reinforced_block")
        trusses = [t for t, (etype, _) in elements.items() if etype == 1 and t in views["dt"]]
        self.assertTrue(trusses)
        self.assertFalse(set(trusses) & set(views["dt calculix"]))
        self.assertTrue(set(trusses) <= set(views["dt lsdyna"]))

    def test_without_option_no_views(self):
        copy_scene("plate_with_hole")
        code, log = tu.run("run", "plate_with_hole.xml", "-q", "-o", "plain.msh")
        self.assertEqual(code, 0, log)
        views, _, _ = mesh_data(tu.path("plain.msh"))
        self.assertFalse([n for n in views if n in ("dt " + s for s in SOLVERS)])

    def test_bad_lists(self):
        copy_scene("plate_with_hole")
        for bad, says in (("lsdyna,nastran", "'nastran' is not a solver; the solvers are: calculix, abaqus, lsdyna"),
                          ("abaqus,abaqus", "abaqus is named twice"), ("lsdyna,", "'' is not a solver"),
                          ("", "'' is not a solver")):
            code, log = tu.run("run", "plate_with_hole.xml", "-o", "bad.msh", "--solver-rule", bad)
            self.assertEqual(code, 2, log)
            self.assertIn(says, log)
            self.assertFalse(os.path.exists(tu.path("bad.msh")))


if __name__ == "__main__":
    tu.main()
