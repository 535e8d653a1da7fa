"""A remesh Gmsh refuses keeps the round number the table shows (issue 43
item 8: the cause of a refused remesh named "round 2" while the table's
round 2 was the next, successful, remesh of another strategy). A remesh
Gmsh refuses or crashes in makes no round, so refine names it by the last
round made before it ("remeshing after round 1"), in the cause, in Gmsh's
stage and in DTMAP_TEST_GMSH_CRASH's stage name (src/gmsh/contain.c).

The plate with a hole of t350 refined at 6x its recommended step with
--max-iter 3: without a crash the size field makes rounds 1-3. With
DTMAP_TEST_GMSH_CRASH = "remeshing after round 1#3" the third contained
Gmsh job (the input's meshing, round 1's remesh, then the size field's
second remesh: measured) raises a real SIGSEGV. The size field ends there
and the other strategies go on, so later remeshes succeed. The cause
names round 1: the report's round 1 is the size field's round, the round
the crashed remesh followed; every round after it is of another strategy
(the size field tried no more), and round 2 exists. The terminal prints
the report's cause word for word.
"""

import os
import re
import subprocess
import unittest

import testutil as tu

GEO = """SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Disk(2) = {0.5, 0.5, 0, 0.2};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
Physical Surface("block") = {3};
"""

SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="plate.geo"/>
<meshing dim="2" size="0.06"/>
<material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="plane-stress"/></effects>
<time duration="1e-4"/>
</dtmap-scene>
"""


class RefusedRound(unittest.TestCase):
    def test_cause_names_the_table_round(self):
        tu.write("plate.geo", GEO)
        tu.write("plate.xml", SCENE)
        code, log = tu.run("run", "plate.xml", "-q", "-o", "plate_dt.msh", "--report", "plate_dt.json")
        self.assertEqual(code, 0, log)
        target = 6.0 * tu.report("plate_dt.json")["dt"]["recommended"]
        env = dict(os.environ)
        env["DTMAP_TEST_GMSH_CRASH"] = "remeshing after round 1#3"
        p = subprocess.run([tu.CLI, "refine", "plate.xml", "--target", "%.6e" % target, "--max-iter", "3",
                            "-o", "plate_r.msh", "--report", "plate_r.json"],
                           cwd=tu.tmpdir(), env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True)
        log = p.stdout
        self.assertEqual(p.returncode, 1, log)
        ref = tu.report("plate_r.json")["refine"]
        crashes = [c for c in ref["causes"] if c["kind"] == "gmsh-crash"]
        self.assertEqual(len(crashes), 1, ref["causes"])
        msg = crashes[0]["message"]
        m = re.match(r"remeshing after round (\d+): Gmsh crashed \(signal 11", msg)
        self.assertIsNotNone(m, msg)
        self.assertIn("(strategy field; Gmsh gave no mesh, so this remesh has no round of its own)", msg)
        k = int(m.group(1))
        rounds = ref["rounds"]
        self.assertEqual([r["round"] for r in rounds], list(range(len(rounds))))
        self.assertEqual(k, 1, msg)
        self.assertEqual(rounds[k]["strategy"], "field", rounds)  # the round the crashed remesh followed
        self.assertGreater(len(rounds), k + 1, log)  # later remeshes succeeded, numbered after it
        self.assertTrue(all(r["strategy"] != "field" for r in rounds[k + 1:]), rounds)
        self.assertIn("[gmsh-crash] " + msg, log)  # the summary says what the report says


if __name__ == "__main__":
    tu.main()
