"""`dtmap run` on a .msh writes the output's mesh as the input's own bytes
where that is the mesh Gmsh would write (src/gmsh/msh_copy.c), and through
Gmsh everywhere else; either way Gmsh reads the output back with the
input's nodes, elements and physical groups, and the views once each.

Gmsh (the real library) meshes a box with a cylinder cut out, keeping its
surfaces and a physical surface besides the volume, and writes it as MSH
4.1 binary and ASCII. Then:
- binary in, binary out: the output starts with the input, byte for byte;
- the output of that run as the next input (it holds the first run's
  views): the copy ends before those views, so each view is in the new
  output once, and the mesh part is again the original file;
- ASCII in, binary out (another encoding) and the same binary file under
  <mesh unit="mm"> (the nodes scaled): not copied, the output's mesh is
  Gmsh's (scaled by 1e-3 in the second);
- in every case the output's mesh is the input's as Gmsh reads it (node
  tags and coordinates, element tags and nodes per entity, physical groups
  and names), and the dt views match between the copied and Gmsh-written
  outputs exactly (the same analysis: the mesh was not changed).
"""

import unittest

import testutil as tu

SCENE = """<dtmap-scene version="1">
  <mesh file="%s"%s/>
  <material name="steel" groups="part" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="3d"/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""


def make_meshes():
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("part")
        box = gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.06, 0.04)
        hole = gmsh.model.occ.addCylinder(0.05, 0.03, -0.01, 0, 0, 0.06, 0.012)
        gmsh.model.occ.cut([(3, box)], [(3, hole)])
        gmsh.model.occ.synchronize()
        vols = [t for _, t in gmsh.model.getEntities(3)]
        gmsh.model.addPhysicalGroup(3, vols, 1)
        gmsh.model.setPhysicalName(3, 1, "part")
        surf = [t for _, t in gmsh.model.getEntities(2)][:2]
        gmsh.model.addPhysicalGroup(2, surf, 2)
        gmsh.model.setPhysicalName(2, 2, "faces")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.012)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.SaveAll", 1)
        gmsh.option.setNumber("Mesh.Binary", 1)
        gmsh.write(tu.path("part_bin.msh"))
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(tu.path("part_ascii.msh"))
    finally:
        gmsh.finalize()


def with_gmsh(path, read):
    """read() on the file at path, open in Gmsh (the real library), quiet."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        return read(gmsh)
    finally:
        gmsh.finalize()


def mesh_of(path):
    """Nodes (tag: xyz), elements per entity and type (tags, nodes), physical groups with names and entities."""
    def read(gmsh):
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        nodes = {int(t): tuple(xyz[3 * i:3 * i + 3]) for i, t in enumerate(tags)}
        elems = {}
        for d, e in gmsh.model.getEntities():
            types, etags, enodes = gmsh.model.mesh.getElements(d, e)
            for t, et, en in zip(types, etags, enodes):
                elems[(d, e, int(t))] = (list(et), list(en))
        groups = {(d, t): (gmsh.model.getPhysicalName(d, t), sorted(gmsh.model.getEntitiesForPhysicalGroup(d, t)))
                  for d, t in gmsh.model.getPhysicalGroups()}
        return nodes, elems, groups
    return with_gmsh(path, read)


def view_names(path):
    """The name of every view in the file, in order, repeats included."""
    return with_gmsh(path, lambda gmsh: [gmsh.option.getString("View[%d].Name" % i)
                                         for i in range(len(gmsh.view.getTags()))])


def read(name):
    with open(tu.path(name), "rb") as f:
        return f.read()


class MeshCopied(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        make_meshes()
        cls.input = mesh_of(tu.path("part_bin.msh"))

    def run_scene(self, name, msh, out, unit=""):
        tu.write(name + ".xml", SCENE % (msh, unit))
        code, text = tu.run("run", name + ".xml", "-q", "--format", "binary", "-o", out)
        self.assertEqual(code, 0, text)
        return read(out)

    def assert_same_mesh(self, out, scale=1.0):
        nodes, elems, groups = mesh_of(tu.path(out))
        ref_nodes, ref_elems, ref_groups = self.input
        self.assertEqual(sorted(nodes), sorted(ref_nodes))
        worst = max(max(abs(a - scale * b) for a, b in zip(nodes[t], ref_nodes[t])) for t in ref_nodes)
        self.assertLessEqual(worst, 1e-15)  # exact: copied, or written by Gmsh from the file's doubles
        self.assertEqual(elems, ref_elems)
        self.assertEqual(groups, ref_groups)

    def test_binary_copied_and_views_not_repeated(self):
        src = read("part_bin.msh")
        out = self.run_scene("first", "part_bin.msh", "first_dt.msh")
        self.assertEqual(out[:len(src)], src)  # the input's bytes, then the views
        self.assertIn(b"$ElementData", out[len(src):])
        self.assert_same_mesh("first_dt.msh")
        names = view_names(tu.path("first_dt.msh"))
        self.assertIn("dt", names)
        self.assertEqual(len(names), len(set(names)))
        # the first output (mesh and views) as the next input: its views are not copied
        again = self.run_scene("again", "first_dt.msh", "again_dt.msh")
        self.assertEqual(again[:len(src)], src)
        self.assertEqual(again.count(b"$ElementData"), out.count(b"$ElementData"))
        self.assertEqual(view_names(tu.path("again_dt.msh")), names)
        self.assert_same_mesh("again_dt.msh")
        a, b = tu.views(tu.path("first_dt.msh")), tu.views(tu.path("again_dt.msh"))
        self.assertEqual(a["dt"], b["dt"])

    def test_ascii_in_binary_out_written_by_gmsh(self):
        src = read("part_ascii.msh")
        out = self.run_scene("ascii", "part_ascii.msh", "ascii_dt.msh")
        self.assertTrue(out.startswith(b"$MeshFormat\n4.1 1 8\n"))  # binary, as asked: Gmsh wrote it
        self.assertNotEqual(out[:len(src)], src)
        self.assert_same_mesh("ascii_dt.msh")
        copied = self.run_scene("bin", "part_bin.msh", "bin_dt.msh")
        self.assertTrue(copied.startswith(read("part_bin.msh")))
        # the ASCII file holds each coordinate to 16 digits, the binary one exactly: the steps agree to
        # rounding (1e-12 relative, what issue 46 allows the dt map to move)
        a, b = tu.views(tu.path("ascii_dt.msh"))["dt"], tu.views(tu.path("bin_dt.msh"))["dt"]
        self.assertEqual(sorted(a), sorted(b))
        self.assertLessEqual(max(abs(a[t] - b[t]) / b[t] for t in b), 1e-12)

    def test_scaled_nodes_written_by_gmsh(self):
        src = read("part_bin.msh")
        out = self.run_scene("mm", "part_bin.msh", "mm_dt.msh", ' unit="mm"')
        self.assertNotEqual(out[:len(src)], src)  # the nodes moved: the file's bytes would be wrong
        self.assert_same_mesh("mm_dt.msh", scale=1e-3)


if __name__ == "__main__":
    tu.main()
