"""The Python module's errors: every dtmap failure raises dtmap.Error with
dtmap's own message (and its code), and leaves the session usable.
Without gmsh.initialize(), on a model with no mesh, with a bad material
value (the message names the line of the generated scene and shows it), an
unknown effect, a physical group that does not exist (the message lists
those that do), a scene file with a bad value (file and line), and a closed
result. The CLI refuses a <model/> scene with exit 2 and says why."""

import os

import gmsh

import dtmap
import testutil as tu

STEEL = {"steel": {"groups": "block", "E": 210e9, "nu": 0.3, "rho": 7850}}


def mesh_box():
    gmsh.model.add("box")
    gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [1]), "block")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
    gmsh.model.mesh.generate(3)


class Errors(tu.unittest.TestCase):
    def expect(self, text, **kwargs):
        with self.assertRaises(dtmap.Error) as cm:
            dtmap.analyse(**kwargs)
        self.assertIn(text, str(cm.exception))
        self.assertEqual(cm.exception.code, 2)
        return str(cm.exception)

    def test_gmsh_not_initialised(self):
        self.expect("Gmsh is not initialised: call gmsh.initialize()", materials=STEEL, effects=["elastic"])

    def test_in_a_session(self):
        gmsh.initialize(["t902", "-v", "0"])
        try:
            self.session_errors()
        finally:
            gmsh.finalize()

    def session_errors(self):
        gmsh.model.add("empty")
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        gmsh.model.occ.synchronize()
        self.expect("the current Gmsh model has no element of dimension 3: mesh it first", materials=STEEL,
                    effects=["elastic"])
        mesh_box()
        bad_nu = {"steel": dict(STEEL["steel"], nu=0.6)}
        msg = self.expect("dtmap.analyse.xml:3:", materials=bad_nu, effects=["elastic"])
        self.assertIn("line 3 of the generated scene: <material name=\"steel\"", msg)
        self.assertIn("nu", msg)
        self.expect("dtmap.analyse.xml:5:", materials=STEEL, effects=["elastik"])
        rock = {"granite": dict(STEEL["steel"], groups="rock")}
        msg = self.expect("physical group 'rock' does not exist", materials=rock, effects=["elastic"])
        self.assertIn("block", msg)  # the groups that exist
        scene = tu.write("bad.xml", '<dtmap-scene version="1">\n  <model/>\n'
                         '  <material name="steel" groups="block" E="-1" nu="0.3" rho="7850"/>\n'
                         '  <effects><elastic/></effects>\n</dtmap-scene>\n')
        self.expect(scene + ":3:", scene=scene)
        with self.assertRaises(ValueError):
            dtmap.analyse(scene=scene, materials=STEEL)
        # After all these, the session still analyses.
        r = dtmap.analyse(materials=STEEL, effects=["elastic"], views=False)
        self.assertGreater(r.recommended, 0)
        r.close()
        with self.assertRaises(dtmap.Error) as cm:
            r.write_report(tu.path("closed.json"))
        self.assertEqual(cm.exception.code, 3)
        self.assertFalse(os.path.exists(tu.path("closed.json")))

    def test_cli_refuses_model(self):
        scene = tu.write("model.xml", '<dtmap-scene version="1">\n  <model/>\n'
                         '  <material name="steel" default="true" E="210e9" nu="0.3" rho="7850"/>\n'
                         '  <effects><elastic/></effects>\n</dtmap-scene>\n')
        code, out = tu.run("run", scene, "-q", "-o", tu.path("m.msh"))
        self.assertEqual(code, 2, out)
        self.assertIn(scene + ":2: <model/> stands for the current Gmsh model", out)
        self.assertFalse(os.path.exists(tu.path("m.msh")))


if __name__ == "__main__":
    tu.main()
