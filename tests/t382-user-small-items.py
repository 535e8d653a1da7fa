"""The smaller things a user hits (issue 43, item 8), each failing on the
dtmap before it:
- an error lands after the summary it follows, on a line of its own, with
  stdout and stderr in one file (`> log 2>&1`): stdout was block-buffered
  and the error came first or mid-word;
- `refine -o X.msh` (and `run -o X.msh`) writes the report the scene's
  <output report> asks for as X.json, so two meshes keep a report each;
- `--solver ls-dyna` (deck) and `--solver-rule LS-DYNA` (run) say did you
  mean lsdyna;
- `<material unit="MPa">` names <dtmap-scene units="mm-t-s"> as the way,
  not "not a number";
- `snapshot nosuch.msh` says the file does not exist;
- refine's `applied` column names every --optimise pass a remesh ran
  (gmsh's was shown nowhere), and a pass that ran in no remesh (netgen,
  which Debian's Gmsh is built without) is said to have changed nothing."""

import os

import testutil as tu

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};
Physical Volume("block") = {1};
"""


def scene(name, material='E="210e9" nu="0.3" rho="7850"', extra=""):
    tu.write("box.geo", GEO)
    return tu.write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="box.geo"/>
  <meshing size="0.04"/>
  <material name="steel" groups="block" %s/>
  <effects><elastic/></effects>
  %s
</dtmap-scene>
""" % (material, extra))


def gmsh_build_options():
    import gmsh
    gmsh.initialize(["t382", "-v", "0"])
    try:
        return gmsh.option.getString("General.BuildOptions")
    finally:
        gmsh.finalize()


def recommended(name):
    code, log = tu.run("run", name + ".xml", "-q", "-o", name + "_probe.msh", "--report", name + "_probe.json")
    assert code == 0, log
    return tu.report(name + "_probe.json")["dt"]["recommended"]


class Small(tu.unittest.TestCase):
    def test_error_after_the_summary(self):
        scene("flush")
        target = 50 * recommended("flush")  # no remesh reaches it in one round
        code, log = tu.run("refine", "flush.xml", "--target", "%.6e" % target, "--max-iter", "1", "-o", "flush_r.msh")
        self.assertEqual(code, 1, log)
        lines = log.splitlines()
        errors = [i for i, l in enumerate(lines) if "dtmap: error:" in l]
        self.assertEqual(len(errors), 1, log)
        self.assertTrue(lines[errors[0]].startswith("dtmap: error: refine: the target"), lines[errors[0]])
        self.assertTrue(any(l.startswith("round") for l in lines[:errors[0]]), log)  # the table came first
        self.assertTrue(any(l.startswith("wrote ") for l in lines[:errors[0]]), log)

    def test_report_named_after_o(self):
        scene("rep", extra='<output report="rep_out.json"/>')
        target = 0.5 * recommended("rep")  # met by the input: no remesh
        for out in ("a", "b"):
            code, log = tu.run("refine", "rep.xml", "--target", "%.6e" % target, "-q", "-o", out + ".msh")
            self.assertEqual(code, 0, log)
            self.assertTrue(os.path.exists(tu.path(out + ".json")), log)
        self.assertFalse(os.path.exists(tu.path("rep_out_refined.json")))
        self.assertEqual(tu.report("a.json")["mesh"]["elements"], tu.report("b.json")["mesh"]["elements"])

    def test_solver_did_you_mean(self):
        scene("solver")
        code, log = tu.run("deck", "solver.xml", "--solver", "ls-dyna")
        self.assertEqual(code, 2, log)
        self.assertIn("unknown solver 'ls-dyna': did you mean lsdyna?", log)
        code, log = tu.run("run", "solver.xml", "--solver-rule", "calculix,LS-DYNA")
        self.assertEqual(code, 2, log)
        self.assertIn("'LS-DYNA' is not a solver (did you mean lsdyna?)", log)
        code, log = tu.run("deck", "solver.xml", "--solver", "nastran")
        self.assertEqual(code, 2, log)
        self.assertNotIn("did you mean", log)

    def test_material_unit_attribute(self):
        scene("unit", 'E="210000" nu="0.3" rho="7.85e-9" unit="MPa"')
        code, log = tu.run("run", "unit.xml", "-q")
        self.assertEqual(code, 2, log)
        self.assertIn("unit.xml:5: material 'steel': unit=\"MPa\" is no attribute of <material>", log)
        self.assertIn('<dtmap-scene units="mm-t-s">', log)
        self.assertNotIn("not a number", log)

    def test_optimise_shown(self):
        scene("opt")
        target = 1.3 * recommended("opt")
        code, log = tu.run("refine", "opt.xml", "--target", "%.6e" % target, "--max-iter", "2", "--optimise",
                           "gmsh,netgen", "-o", "opt_r.msh", "--report", "opt_r.json")
        self.assertIn(code, (0, 1), log)
        rounds = [l for l in log.splitlines() if l.strip().startswith(("1 ", "2 ")) and ("nodal" in l or "elem." in l)]
        self.assertTrue(rounds, log)
        for l in rounds:
            self.assertTrue(l.rstrip().split("  target met")[0].split("  (kept)")[0].endswith(", gmsh"), l)
        rep = tu.report("opt_r.json")["refine"]["rounds"]
        self.assertTrue(all(r["optimisers"] == ["gmsh"] for r in rep if r["kind"] == "mesh"), rep)
        gmsh_has_netgen = "Netgen" in gmsh_build_options()
        if not gmsh_has_netgen:
            self.assertIn("--optimise netgen: changed nothing, it ran in no remesh (Netgen is not built into this "
                          "Gmsh", log)

    def test_snapshot_of_a_missing_file(self):
        code, log = tu.run("snapshot", "nosuch.msh")
        self.assertEqual(code, 2, log)
        self.assertIn("nosuch.msh: no such file", log)


if __name__ == "__main__":
    tu.main()
