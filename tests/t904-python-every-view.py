"""Views every script can read: a Python script that opens a result of
`dtmap run` (Gmsh merges its .opt) and calls gmsh.view.getModelData on every
view reads them all. Gmsh 4.8 throws a C++ exception past its C API for a
list-based view there, which aborts the interpreter; the .opt used to make
two (the "dt skin" copy of dt, made by the MathEval plugin, and the text
view "dtmap"). Each bundled scene of geometries/ is run (the reinforced
block is the one with "dt skin", here with --solver-rule too), and the
script runs in a child /usr/bin/python3 per output so that an abort is
reported, not suffered: it must exit 0 having read every view, each with
one value per element or node it names.
"""

import glob
import os
import shutil
import subprocess
import sys
import unittest

import testutil as tu

READER = r'''
import sys
import gmsh
gmsh.initialize(["reader", "-v", "0"])
gmsh.open(sys.argv[1])
for tag in gmsh.view.getTags():
    name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(tag))
    kind, tags, data, time, ncomp = gmsh.view.getModelData(tag, 0)
    assert kind in ("ElementData", "NodeData") and len(tags) == len(data) > 0, name
    print("read", name, kind, len(tags), flush=True)
gmsh.finalize()
'''


class EveryView(unittest.TestCase):
    def test_bundled_outputs(self):
        reader = tu.write("reader.py", READER)
        scenes = sorted(glob.glob(os.path.join(tu.SRC, "geometries", "*.xml")))
        self.assertGreaterEqual(len(scenes), 7)
        names = set()
        for scene in scenes:
            name = os.path.basename(scene)[:-4]
            for ext in (".geo", ".xml"):
                shutil.copy(os.path.join(tu.SRC, "geometries", name + ext), tu.tmpdir())
            extra = ["--solver-rule", "lsdyna,abaqus,calculix"] if name == "reinforced_block" else []
            code, log = tu.run("run", name + ".xml", "-q", "-o", name + "_out.msh", *extra)
            self.assertEqual(code, 0, log)
            p = subprocess.run([sys.executable, reader, tu.path(name + "_out.msh")], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, universal_newlines=True, env=tu.plain_env())
            self.assertEqual(p.returncode, 0, "%s: %s" % (name, p.stdout))
            read = [line.split(" ", 1)[1] for line in p.stdout.splitlines() if line.startswith("read ")]
            self.assertIn("dt", [r.rsplit(" ", 2)[0] for r in read])
            names.update(r.rsplit(" ", 2)[0] for r in read)
        self.assertIn("dt skin", names)  # the reinforced block's, model-based now
        self.assertIn("dt calculix", names)


if __name__ == "__main__":
    tu.main()
