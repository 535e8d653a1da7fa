"""A .msh that holds its mesh twice is refused, not analysed with every
element counted twice (issue 43 item 7; src/mesh/duplicates.c).

- Gmsh (the real library) meshes a box and writes it; a view of its
  elements is appended to a copy with PostProcessing.SaveMesh = 1, which
  writes the mesh again (two $Nodes and two $Elements sections; Gmsh reads
  every element twice). `dtmap run` on the copy exits 2, names the file,
  counts the repeated elements (all of the box's), says why and what to
  do, and writes no output; the original file runs (exit 0) with the
  box's element count.
- A msh 2.2 written here with one tetrahedron listed again under another
  tag on the same nodes in another order: exit 2 naming both tags.
"""

import os
import unittest

import testutil as tu

SCENE = """<dtmap-scene version="1">
  <mesh file="%s"/>
  <material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="3d"/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""


def box_with_view():
    """box.msh and box_view.msh (the mesh, then a view appended with the mesh saved again); the tet count."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box")
        v = gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.1, 0.1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [v], 1)
        gmsh.model.setPhysicalName(3, 1, "block")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.03)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(tu.path("box.msh"))
        gmsh.write(tu.path("box_view.msh"))
        tags, _ = gmsh.model.mesh.getElementsByType(4)
        view = gmsh.view.add("marks")
        gmsh.view.addHomogeneousModelData(view, 0, "box", "ElementData", tags, [1.0] * len(tags))
        gmsh.option.setNumber("PostProcessing.SaveMesh", 1)
        gmsh.view.write(view, tu.path("box_view.msh"), append=True)
        return len(tags)
    finally:
        gmsh.finalize()


class Duplicated(unittest.TestCase):
    def test_view_appended_with_the_mesh(self):
        ntets = box_with_view()
        with open(tu.path("box_view.msh")) as f:
            self.assertEqual(f.read().count("$Elements\n"), 2)  # the file does hold the mesh twice
        tu.write("once.xml", SCENE % "box.msh")
        code, out = tu.run("run", "once.xml", "-q", "-o", "once_dt.msh", "--report", "once.json")
        self.assertEqual(code, 0, out)
        self.assertEqual(tu.report("once.json")["mesh"]["elements"], ntets)
        tu.write("twice.xml", SCENE % "box_view.msh")
        code, out = tu.run("run", "twice.xml", "-q", "-o", "twice_dt.msh", "--report", "twice.json")
        self.assertEqual(code, 2, out)
        self.assertIn("box_view.msh: the mesh is in the file twice: %d elements repeat" % ntets, out)
        self.assertIn("the same tag listed twice", out)
        self.assertIn("PostProcessing.SaveMesh", out)
        self.assertIn("write the mesh alone", out)
        self.assertFalse(os.path.exists(tu.path("twice_dt.msh")))
        self.assertFalse(os.path.exists(tu.path("twice.json")))

    def test_one_element_listed_again(self):
        nodes = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]
        tets = [(1, 2, 3, 4), (2, 3, 4, 5), (2, 3, 1, 4)]  # the third: the first's nodes again, not inverted
        lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "1", '3 1 "block"',
                 "$EndPhysicalNames", "$Nodes", str(len(nodes))]
        lines += ["%d %g %g %g" % (i + 1, *x) for i, x in enumerate(nodes)]
        lines += ["$EndNodes", "$Elements", str(len(tets))]
        lines += ["%d 4 2 1 1 %d %d %d %d" % (10 + e, *t) for e, t in enumerate(tets)]
        tu.write("again.msh", "\n".join(lines + ["$EndElements", ""]))
        tu.write("again.xml", SCENE % "again.msh")
        code, out = tu.run("run", "again.xml", "-q", "-o", "again_dt.msh")
        self.assertEqual(code, 2, out)
        self.assertIn("again.msh: the mesh is in the file twice: 1 element repeats", out)
        self.assertRegex(out, r"element 1[02] \(tet4\) in group 'block' at .*, and element 1[02]\)")
        self.assertFalse(os.path.exists(tu.path("again_dt.msh")))


if __name__ == "__main__":
    tu.main()
