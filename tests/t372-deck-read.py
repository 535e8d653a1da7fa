"""The decks of `dtmap deck` read back by readers written from the solvers'
manuals (tests/common/deckread.py: Abaqus-style commas, LS-DYNA's fixed
columns), against the mesh `dtmap run` writes for the same scene (read with
Gmsh's API; one thread, Delaunay: the same mesh and tags) and the scene:

- the nodes are those of the analysed elements, the elements are the
  analysed ones with their nodes (the connectivity as a set: the solvers
  order nodes their own way); CalculiX's beams on shell nodes have nodes
  of their own, each at its shell node and tied to it by three *EQUATIONs
  (the stiffened panel's 25), read back to the shell node;
- one element set per physical group of the analysed elements, holding
  exactly its elements, and one node set per physical group (also the
  groups below the analysed dimension), holding exactly its nodes;
- the materials carry the scene's E, nu and rho, the sections its
  thickness, area and beam profile (Abaqus: exactly; LS-DYNA's 10-column
  fields, 5 digits for 3.3333e-09: within 2e-5);
- the step: the *DYNAMIC increment is the report's step within 1e-14 (15
  digits in CalculiX's 20 columns); LS-DYNA's TSSFAC is the report's, and
  times the report's own estimate it is the deck's step, at most dtmap's
  recommended one; LS-DYNA's LCTM names a *DEFINE_CURVE flat at the deck's
  step (never above it, within 1e-14 below: 15 digits in 20 columns) from
  time 0 to at least ENDTIM; the LS-DYNA and Abaqus headers say the step
  was proven for the undeformed mesh;
- LS-DYNA's cards are readable: every card of more than one field is in
  free format, its fields separated by commas, none empty or holding a
  blank, each within its fixed columns (the reader refuses a longer one:
  the same digits as fixed columns);
- the shells' transverse shear factor (SHRF) is dtmap's 5/6 (within 1e-8:
  8 digits in 10 columns), as the beams' is;
- with --target (LS-DYNA: --lsdyna-step proven) the mass elements add up to the report's added mass (and to
  its mass_scaling.total_added) within 1e-10;
- a refined mesh that carries point masses (refine's 'added mass at nodes'
  on the extruded slab of tests/data/refine, met with 40 % mass at most):
  every deck has a mass element at each of its nodes, adding up to the
  refine report's total within 1e-10, and the deck's step is on the
  masses (at least the target).

Scenes: the bundled reinforced block (tetrahedra, trusses, a membrane),
stiffened panel (shells, a beam), Brazilian disc (plane strain, with lines
below it), plate with a hole (plane stress), box (with --target), and two
written here: a box of hexahedra and a rectangle of quadrangles (plane
strain); Abaqus also takes a box of tet10."""

import os
import shutil
import unittest

import gmsh

import deckread
import testutil as tu

TET = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.05, 0.04};
Physical Volume("block") = {1};
Physical Surface("left") = {1};
"""
HEX = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.05, 0.04};
Physical Volume("block") = {1};
Physical Surface("left") = {1};
Transfinite Curve{:} = 4; Transfinite Surface{:}; Recombine Surface{:}; Transfinite Volume{1};
"""
QUAD = """SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 0.1, 0.05};
Physical Surface("slab") = {1};
Physical Curve("bottom") = {1};
Transfinite Curve{:} = 5; Transfinite Surface{1}; Recombine Surface{1};
"""
SLAB = """<?xml version="1.0"?>
<dtmap-scene version="1">
  %s
  <meshing dim="3"/>
  <material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="3d"/></effects>
  <time duration="1e-4"%s/>
</dtmap-scene>
"""
SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s.geo"/>
  <meshing size="0.02" order="%d" dim="%d"/>
  <material name="steel" groups="%s" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic%s/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""


def written(name, dim, group, order=1, form=""):
    tu.write(name + ".geo", {"hex": HEX, "quad": QUAD, "tet10": TET}[name.split("_")[0]])
    return tu.write(name + ".xml", SCENE % (name, order, dim, group, form))


def msh_of(scene, name):
    """{(dim, group name): (element tags, node tags)} of the mesh `dtmap run` writes, and the analysed dimension."""
    code, out = tu.run("run", scene, "-q", "-o", tu.path(name + ".msh"), "--report", tu.path(name + "_run.json"))
    if code:
        raise AssertionError("dtmap run %s: %s" % (scene, out))
    gmsh.initialize(["t372", "-v", "0"])
    try:
        gmsh.open(tu.path(name + ".msh"))
        groups = {}
        for dim, tag in gmsh.model.getPhysicalGroups():
            elems = set()
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                for tags in gmsh.model.mesh.getElements(dim, ent)[1]:
                    elems |= {int(t) for t in tags}
            nodes = {int(t) for t in gmsh.model.mesh.getNodesForPhysicalGroup(dim, tag)[0]}
            groups[(dim, gmsh.model.getPhysicalName(dim, tag).upper())] = (elems, nodes)
        return groups
    finally:
        gmsh.finalize()


def deck(scene, name, solver, *extra):
    ext = ".k" if solver == "lsdyna" else ".inp"
    out, rep = tu.path(name + "_" + solver + ext), tu.path(name + "_" + solver + ".json")
    code, text = tu.run("deck", scene, "--solver", solver, "-o", out, "--report", rep, "-q", *extra)
    if code:
        raise AssertionError("dtmap deck %s --solver %s: exit %d\n%s" % (scene, solver, code, text))
    r = tu.report(rep)
    return (deckread.read_k if solver == "lsdyna" else deckread.read_inp)(out), r


def analysed(groups, rep, scene_sections):
    """The groups whose elements are analysed: the mesh's dimension, and the sectioned ones below."""
    dim = rep["mesh"]["dim"]
    return {k: v for k, v in groups.items() if k[0] == dim or k[1] in scene_sections}


class Reader(unittest.TestCase):
    def element_sets(self, d, solver):
        """{set name: element ids} (LS-DYNA's part sets made element sets)."""
        if solver != "lsdyna":
            return d.elsets
        out = {}
        for name, (kind, ids) in d.elsets.items():
            out[name] = {e for e, v in d.elements.items() if v[2] in ids} if kind == "parts" else ids
        return out

    def twins(self, d):
        """{beam node: shell node} of CalculiX's beams on nodes of their own:
        each tied to a node at the same place by three *EQUATIONs
        (translations equal)."""
        out = {}
        for eq in d.equations:
            self.assertEqual(len(eq), 2)
            (a, da, ca), (b, db, cb) = eq
            self.assertEqual((da, ca, cb), (db, 1.0, -1.0))
            self.assertEqual(d.nodes[a], d.nodes[b])
            out[a] = b
        for a in out:
            self.assertEqual(sorted(eq[0][1] for eq in d.equations if eq[0][0] == a), [1, 2, 3])
        return out

    def check_mesh(self, d, rep, groups, solver, sectioned=()):
        mine = analysed(groups, rep, sectioned)
        elems = set().union(*(e for e, _ in mine.values()))
        nodes = set().union(*(n for _, n in mine.values()))
        mass_ids = set(d.masses)
        self.assertEqual(set(d.elements) - mass_ids, elems)
        self.assertEqual(set(d.nodes) - set(self.twins(d)), nodes)
        self.assertEqual(rep["deck"]["nodes"], len(nodes))
        self.assertEqual(rep["deck"]["elements"], len(elems))
        sets = self.element_sets(d, solver)
        for (dim, name), (e, n) in groups.items():
            if (dim, name) in mine:
                self.assertEqual(sets[name], e, "element set %s" % name)
            self.assertEqual(d.nsets[name], n & nodes, "node set %s" % name)

    def connectivity(self, d, scene_name):
        gmsh.initialize(["t372", "-v", "0"])
        try:
            gmsh.open(tu.path(scene_name + ".msh"))
            twin = self.twins(d)
            for eid, v in list(d.elements.items())[:200] + [e for e in d.elements.items() if e[1][0] == "B31"]:
                if eid in d.masses:
                    continue
                _, nodes = gmsh.model.mesh.getElement(eid)[:2]
                self.assertEqual({twin.get(n, n) for n in v[1]}, {int(t) for t in nodes}, "element %d" % eid)
        finally:
            gmsh.finalize()

    def materials(self, d, solver, want):
        got = {}
        for k, v in d.materials.items():
            got[v[0] if solver == "lsdyna" else k] = tuple(v[1:4]) if solver == "lsdyna" else tuple(v)
        for name, (E, nu, rho) in want.items():
            self.assertEqual(got[name], (E, nu, rho), name)

    def steps(self, d, rep, solver, path):
        dk = rep["deck"]
        if solver == "lsdyna":
            self.assertEqual(d.controls["tssfac"], dk["tssfac"])
            self.assertLessEqual(dk["tssfac"], 0.9)  # LS-DYNA's convention (issue 43); DT2MS beyond it
            scaled = -dk["dt2ms"] if "dt2ms" in dk else dk["own_estimate"]
            self.assertLess(abs(d.controls["tssfac"] * scaled / dk["step"] - 1), 1e-15)
            self.assertLessEqual(dk["step"], dk["recommended"])
            self.assertEqual(d.controls["endtim"], dk["duration"])
            curve = d.curves[d.controls["lctm"]]  # the cap on every step
            self.assertEqual(curve[0][0], 0.0)
            self.assertGreaterEqual(curve[-1][0], dk["duration"])
            for _, cap in curve:
                self.assertLessEqual(cap, dk["step"])
                self.assertLess(1 - cap / dk["step"], 1e-14)
            self.separated(path)
        else:  # 15 digits in CalculiX's 20 columns
            self.assertLess(abs(d.controls["dynamic"][1][0] / dk["step"] - 1), 1e-14)
            self.assertLess(abs(d.controls["dynamic"][1][1] / dk["duration"] - 1), 1e-14)
        if solver in ("lsdyna", "abaqus"):
            with open(path) as f:
                head = [line.lstrip("$*").strip() for line in f.read().split("\n")[:30]]
            self.assertTrue(any(h.startswith("The step was proven for the undeformed mesh.") for h in head), path)

    def separated(self, path):
        """Every LS-DYNA card of more than one field: commas between its
        fields, none empty or holding a blank (titles are one field)."""
        with open(path) as f:
            lines = f.read().split("\n")
        title, cards = False, 0
        for n, line in enumerate(lines, 1):
            if line.startswith("*"):
                key = line[1:].strip().upper()
                title = key.endswith("_TITLE") or key in ("TITLE", "PART")
                continue
            if not line.strip() or line.startswith("$"):
                continue
            if title:
                title = False
                continue
            cards += 1
            where = "%s:%d: %r" % (path, n, line)
            fields = line.split(",")
            if len(fields) == 1:  # one field in its columns
                self.assertEqual(len(line.split()), 1, where)
                continue
            for t in fields:
                self.assertTrue(t and " " not in t, where)
        self.assertGreater(cards, 10)

    def scene(self, scene, name, solvers=("abaqus", "lsdyna", "calculix"), sectioned=(), mats=None):
        groups = msh_of(scene, name)
        out = {}
        for solver in solvers:
            with self.subTest(scene=name, solver=solver):
                d, rep = deck(scene, name, solver)
                self.check_mesh(d, rep, groups, solver, sectioned)
                self.connectivity(d, name)
                ext = ".k" if solver == "lsdyna" else ".inp"
                self.steps(d, rep, solver, tu.path(name + "_" + solver + ext))
                if mats:
                    self.materials(d, solver, mats)
                out[solver] = (d, rep)
        return out

    def test_reinforced_block(self):
        steel, concrete = (200e9, 0.3, 7850.0), (30e9, 0.2, 2400.0)
        decks = self.scene(os.path.join(tu.SRC, "geometries", "reinforced_block.xml"), "reinforced",
                           sectioned=("PLATE", "REBAR"), mats={"STEEL": steel, "CONCRETE": concrete})
        ab = decks["abaqus"][0].sections
        self.assertEqual(ab["REBAR"][0], "SOLID SECTION")
        self.assertEqual(ab["REBAR"][2], [[3.1e-4]])
        self.assertEqual(ab["PLATE"][0], "MEMBRANE SECTION")
        self.assertEqual(ab["PLATE"][2], [[0.01]])
        ls = decks["lsdyna"][0].sections["sections"]
        by_title = {v[1]: v for v in ls.values()}
        self.assertEqual(float(by_title["REBAR"][2][1][0]), 3.1e-4)
        self.assertEqual(by_title["REBAR"][2][0][1], "3")  # ELFORM 3: truss
        self.assertEqual(float(by_title["PLATE"][2][1][0]), 0.01)
        self.assertEqual(by_title["PLATE"][2][0][1], "5")  # ELFORM 5: membrane

    def test_stiffened_panel(self):
        decks = self.scene(os.path.join(tu.SRC, "geometries", "stiffened_panel.xml"), "panel",
                           sectioned=("STIFFENER",), mats={"STEEL": (200e9, 0.3, 7850.0)})
        b, h = 0.01, 0.04
        want = [b * h, b * h ** 3 / 12, h * b ** 3 / 12]
        ab = decks["abaqus"][0].sections
        self.assertEqual(ab["SKIN"][2], [[0.005]])
        self.assertEqual(ab["STIFFENER"][0], "BEAM GENERAL SECTION")
        got = ab["STIFFENER"][2][0]
        for g, w in zip([got[0], got[1], got[3]], want):
            self.assertLess(abs(g / w - 1), 1e-12)
        self.assertEqual(ab["STIFFENER"][2][1], [1.0, 0.0, 0.0])  # n1: the scene's orientation
        ls = {v[1]: v for v in decks["lsdyna"][0].sections["sections"].values()}
        for name in ("SKIN", "STIFFENER"):  # SHRF: dtmap's shear factor
            self.assertLess(abs(float(ls[name][2][0][2]) / (5 / 6) - 1), 1e-8, name)
        got = [float(x) for x in ls["STIFFENER"][2][1][:3]]
        for g, w in zip(got, want):
            self.assertLess(abs(g / w - 1), 2e-5)
        beams = [v for v in decks["lsdyna"][0].elements.values() if v[0] == "ELEMENT_BEAM_ORIENTATION"]
        self.assertEqual(len(beams), 24)
        self.assertEqual(len(self.twins(decks["calculix"][0])), 25)  # CalculiX's beams: nodes of their own
        self.assertTrue(all(v[3] == (1.0, 0.0, 0.0) for v in beams))

    def test_plane(self):
        self.scene(os.path.join(tu.SRC, "geometries", "brazilian_disc.xml"), "disc",
                   mats={"GRANITE": (60e9, 0.25, 2700.0), "STEEL": (210e9, 0.3, 7850.0)})
        decks = self.scene(os.path.join(tu.SRC, "geometries", "plate_with_hole.xml"), "plate")
        self.assertEqual(decks["abaqus"][0].sections["PLATE"][2], [[1.0]])  # plane stress, per unit thickness
        self.assertEqual({v[0] for v in decks["abaqus"][0].elements.values()}, {"CPS3"})

    def test_hexahedra_quadrangles_tet10(self):
        decks = self.scene(written("hex", 3, "block"), "hex")
        self.assertEqual({v[0] for v in decks["abaqus"][0].elements.values()}, {"C3D8"})
        self.assertTrue(all(len(v[1]) == 8 for v in decks["lsdyna"][0].elements.values()))
        decks = self.scene(written("quad", 2, "slab", form=' formulation="plane-strain"'), "quad")
        self.assertEqual({v[0] for v in decks["calculix"][0].elements.values()}, {"CPE4"})
        decks = self.scene(written("tet10", 3, "block", order=2), "tet10", solvers=("abaqus", "calculix"))
        self.assertEqual({v[0] for v in decks["calculix"][0].elements.values()}, {"C3D10"})

    def test_carried_masses(self):
        """A refined mesh that carries point masses ('added mass at nodes'):
        every deck writes them at their nodes, adding up to the report's."""
        shutil.copy(os.path.join(tu.SRC, "tests", "data", "refine", "extruded.geo"), tu.path("extruded.geo"))
        slab = tu.write("slab.xml", SLAB % ('<geometry file="extruded.geo"/>', ""))
        code, out = tu.run("run", slab, "-q", "-o", tu.path("slab_dt.msh"), "--report", tu.path("slab_dt.json"))
        self.assertEqual(code, 0, out)
        target = 1.15 * tu.report("slab_dt.json")["dt"]["recommended"]
        code, out = tu.run("refine", slab, "--target", "%.9e" % target, "--max-added-mass", "40", "-q", "-o",
                           tu.path("slab_r.msh"), "--report", tu.path("slab_r.json"))
        self.assertEqual(code, 0, out)
        pm = tu.report("slab_r.json")["point_masses"]
        again = tu.write("slab_again.xml", SLAB % ('<mesh file="slab_r.msh"/>', ""))
        for solver in ("abaqus", "lsdyna", "calculix"):
            with self.subTest(solver=solver):
                d, rep = deck(again, "slab", solver)
                total = sum(m for _, m in d.masses.values())
                self.assertEqual(rep["deck"]["carried_nodes"], pm["nodes"])
                self.assertEqual(len(d.masses), pm["nodes"])
                self.assertLess(abs(total / pm["total"] - 1), 1e-10)
                self.assertLess(abs(rep["deck"]["carried_mass"] / pm["total"] - 1), 1e-12)
                self.assertGreaterEqual(rep["deck"]["recommended"], target * (1 - 1e-12))

    def test_masses(self):
        scene = os.path.join(tu.SRC, "geometries", "box.xml")
        for solver in ("abaqus", "lsdyna", "calculix"):
            with self.subTest(solver=solver):
                proven = ("--lsdyna-step", "proven") if solver == "lsdyna" else ()  # dtmap's nodal masses
                d, rep = deck(scene, "box", solver, "--target", "6e-7", *proven)
                total = sum(m for _, m in d.masses.values())
                self.assertGreater(rep["deck"]["added_nodes"], 0)
                self.assertEqual(len(d.masses), rep["deck"]["added_nodes"])
                self.assertLess(abs(total / rep["deck"]["added_mass"] - 1), 1e-10)
                self.assertLess(abs(total / rep["mass_scaling"]["total_added"] - 1), 1e-10)


if __name__ == "__main__":
    tu.main()
