"""The Python module on a live Gmsh model, against `dtmap run` on the same
mesh: the example script (python/examples/box.py) prints the recommended
step of `dtmap run` digit for digit; in this process, a box built and
meshed with Gmsh's API gives the arrays and steps of the CLI's report and
views; the views land in the open session with the .opt's display options;
a scene file (the bundled plate, meshed here with the scene's options) with
--posterior matches the CLI; and the reports the module writes follow the
schema (checked as the script ends).

Tolerances: the meshes are bit-identical (written in binary .msh, or
meshed by the same Gmsh on one thread with the same options) and the
in-process numbers come from the same code, so the steps are the same
doubles; but the report is written by cJSON, which prints 15 significant
digits whenever they read back within DBL_EPSILON relative, so values read
from a report are compared at DBL_EPSILON relative (one unit in the last
place), and the CLI's views go through the ASCII .msh, which keeps 16
significant digits, hence 1e-15 relative there; the global estimate is
compared at 1e-12 relative, the order of OpenMP's partial sums in the
Lanczos products being the only thing that may differ.
"""

import os
import subprocess
import sys

import gmsh
import numpy

import dtmap
import testutil as tu

EPS = sys.float_info.epsilon


def same_double(test, a, b):
    """a (a double) and b (read from a report) are the same double as cJSON prints it."""
    test.assertLessEqual(abs(a - b), EPS * max(abs(a), abs(b)), "%r != %r" % (a, b))


STEEL = {"steel": {"groups": "block", "E": 210e9, "nu": 0.3, "rho": 7850}}
STEEL_XML = '<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>'


def mesh_box(size=0.02):
    """A 0.1 m box with the physical volume "block", meshed, also written as box.msh (binary)."""
    gmsh.model.add("box")
    gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.1, 0.1)
    gmsh.model.occ.synchronize()
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(tu.path("box.msh"))
    gmsh.option.setNumber("Mesh.Binary", 0)


def cli_on(mesh, effects="<elastic/>", extra=()):
    """`dtmap run` on a <mesh> scene with the steel block; returns the report."""
    tu.write("cli.xml", '<dtmap-scene version="1">\n  <mesh file="%s"/>\n  %s\n  <effects>%s</effects>\n'
             '</dtmap-scene>\n' % (mesh, STEEL_XML, effects))
    code, out = tu.run("run", "cli.xml", "-q", "-o", "cli_dt.msh", "--report", "cli.json", *extra)
    assert code == 0, out
    return tu.report("cli.json")


STYLE = ("Light", "ScaleType", "ColormapNumber", "IntervalsType", "NbIso", "Visible", "ColormapAlpha", "DrawSkinOnly",
         "ShowScale")


def style(tag):
    """The display options dtmap sets on a view (numbers, and the legend's format)."""
    i = gmsh.view.getIndex(tag)
    out = {o: gmsh.option.getNumber("View[%d].%s" % (i, o)) for o in STYLE}
    out["Format"] = gmsh.option.getString("View[%d].Format" % i)
    return out


def views_of_file(path, read=()):
    """{name: (tags, values) for the names in read, else the view's style} of the
    views a .msh brings into the session with its .opt (which also adds a text
    view, "dtmap", without model data)."""
    before = set(gmsh.view.getTags())
    gmsh.merge(path)
    out = {}
    for t in gmsh.view.getTags():
        if t in before:
            continue
        name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(t))
        out[name] = style(t)
        if name in read:
            _, tags, data, _, _ = gmsh.view.getModelData(t, 0)
            out[name] = (numpy.array(tags, dtype=numpy.uint64), numpy.array([d[0] for d in data]))
    for t in set(gmsh.view.getTags()) - before:
        gmsh.view.remove(t)
    return out


class Analyse(tu.unittest.TestCase):
    def setUp(self):
        gmsh.initialize(["t901", "-v", "0"])

    def tearDown(self):
        gmsh.finalize()

    def test_example_script_prints_the_cli_step(self):
        env = dict(os.environ)
        script = os.path.join(tu.SRC, "python", "examples", "box.py")
        out = subprocess.run([sys.executable, script], cwd=tu.tmpdir(), env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertEqual(out.returncode, 0, out.stdout)
        printed = float(out.stdout.split("recommended step ")[1].split()[0])
        tu.write("box_default.xml", '<dtmap-scene version="1">\n  <mesh file="box.msh"/>\n'
                 '  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>\n'
                 '  <effects><elastic/></effects>\n</dtmap-scene>\n')
        code, log = tu.run("run", "box_default.xml", "-q", "-o", "box_dt.msh", "--report", "box_default.json")
        self.assertEqual(code, 0, log)
        same_double(self, printed, tu.report("box_default.json")["dt"]["recommended"])

    def test_live_model_matches_the_cli(self):
        mesh_box()
        r = dtmap.analyse(materials=STEEL, effects=["elastic"], views=False)
        rep = cli_on("box.msh")
        dt = rep["dt"]
        same_double(self, r.recommended, dt["recommended"])
        self.assertEqual(r.basis, dt["basis"])
        same_double(self, r.dt_min, dt["min"])
        self.assertEqual(r.dt_min_element, dt["element"])
        same_double(self, r.dt_nodal, dt["nodal"])
        self.assertTrue(numpy.isnan(r.dt_global))
        self.assertEqual(r.effects, rep["effects"])
        self.assertEqual(len(r.dt), rep["mesh"]["elements"])
        self.assertEqual(len(r.node_tags), rep["mesh"]["nodes"])
        # The arrays against the CLI's views, element by element and node by node.
        views = views_of_file(tu.path("cli_dt.msh"), read=("dt", "characteristic length", "nodal dt"))
        for name, tags, values in (("dt", r.element_tags, r.dt), ("characteristic length", r.element_tags, r.length),
                                   ("nodal dt", r.node_tags, r.nodal_dt)):
            vtags, vvalues = views[name]
            order = numpy.argsort(vtags)
            mine = numpy.argsort(tags)
            numpy.testing.assert_array_equal(vtags[order], tags[mine])
            numpy.testing.assert_allclose(vvalues[order], values[mine], rtol=1e-15, atol=0)
        self.assertEqual(r.dt.min(), r.dt_min)
        self.assertEqual(r.element_tags[numpy.argmin(r.dt)], r.dt_min_element)
        self.assertEqual(r.nodal_dt.min(), r.dt_nodal)
        r.close()

    def test_views_in_the_session(self):
        mesh_box()
        r = dtmap.analyse(materials=STEEL, effects=["elastic"])
        for name in ("dt", "characteristic length", "limiting effect", "size suggestion", "nodal dt",
                     "subcycling level", "dt elastic"):
            self.assertIn(name, r.views)
        _, tags, data, _, _ = gmsh.view.getModelData(r.views["dt"], 0)
        by_tag = dict(zip(tags, (d[0] for d in data)))
        self.assertEqual([by_tag[int(t)] for t in r.element_tags], list(r.dt))
        self.assertEqual(style(r.views["dt"])["ScaleType"], 2)  # log scale
        self.assertEqual(style(r.views["characteristic length"])["Visible"], 0)  # hidden until ticked
        r.write_report(tu.path("live.json"))
        gmsh.option.setNumber("Mesh.Binary", 1)  # the script's own choice, which writing must not change
        r.write(tu.path("live_dt.msh"))
        self.assertEqual(gmsh.option.getNumber("Mesh.Binary"), 1)
        self.assertEqual(gmsh.option.getNumber("PostProcessing.SaveMesh"), 1)
        self.assertTrue(os.path.exists(tu.path("live_dt.msh.opt")))
        # The session's views are styled as the .msh's .opt styles them on opening.
        opened = views_of_file(tu.path("live_dt.msh"))
        self.assertEqual(set(opened) - {"dtmap"}, set(r.views))
        for name, tag in r.views.items():
            self.assertEqual(style(tag), opened[name], name)
        same_double(self, r.recommended, tu.report("live.json")["dt"]["recommended"])
        self.assertEqual(tu.report("live.json")["scene"], "dtmap.analyse.xml")

    def test_scene_file_with_posterior(self):
        scene = os.path.join(tu.SRC, "geometries", "plate_with_hole.xml")
        gmsh.open(os.path.join(tu.SRC, "geometries", "plate_with_hole.geo"))
        # What dtmap run does with the scene's <meshing size="5e-3" min-size="1e-3"/>, on one thread.
        gmsh.option.setNumber("Mesh.MeshSizeMax", 5e-3)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 1e-3)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.mesh.generate(2)
        r = dtmap.analyse(scene=scene, posterior=True)
        code, out = tu.run("run", scene, "-q", "--posterior", "-o", "plate_dt.msh", "--report", "plate.json")
        self.assertEqual(code, 0, out)
        dt = tu.report("plate.json")["dt"]
        self.assertEqual(len(r.dt), tu.report("plate.json")["mesh"]["elements"])
        same_double(self, r.dt_min, dt["min"])
        self.assertEqual(r.basis, dt["basis"])
        self.assertLessEqual(abs(r.dt_global - dt["global"]), 1e-12 * dt["global"])
        self.assertLessEqual(abs(r.recommended - dt["recommended"]), 1e-12 * dt["recommended"])
        r.write_report(tu.path("plate_py.json"))
        self.assertIn("lanczos", tu.report("plate_py.json")["effect_minima"][0])

    def test_versions(self):
        v = dtmap.version()
        self.assertEqual(v["dtmap"], dtmap.__version__)
        self.assertEqual(v["gmsh"], gmsh.option.getString("General.Version"))
        self.assertEqual(v["effect_api"], tu.effect_api_version())

    def test_one_libgmsh(self):
        # gmsh.py and libdtmap share the libgmsh of this process ...
        self.assertEqual(dtmap._lib.mapped_gmsh(), [dtmap.GMSH_LIBRARY])
        self.assertTrue(os.path.basename(dtmap.GMSH_LIBRARY).startswith("libgmsh.so"))
        # ... and two different files would be seen.
        ours, other = dtmap.GMSH_LIBRARY, "/opt/gmsh/lib/libgmsh.so.4.8"
        fake = tu.write("maps", "7f00-7f01 r-xp 0 08:01 1 %s\n7f02-7f03 r-xp 0 08:01 2 %s\n"
                        "7f04-7f05 r--p 0 08:01 1 %s\n7f06-7f07 rw-p 0 00:00 0\n" % (ours, other, ours))
        self.assertEqual(dtmap._lib.mapped_gmsh(fake), sorted([ours, other]))


if __name__ == "__main__":
    tu.main()
