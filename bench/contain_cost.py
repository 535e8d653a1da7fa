"""What handing a mesh back from a child process costs (src/gmsh/contain.c):
what each remesh of `dtmap refine` pays (the first mesh of a command is made
in the supervised worker and handed nowhere; bench/perf.sh measures that
supervisor against one process).

The child inherits the session by fork, meshes, writes its mesh as a binary
.msh and exits; the parent clears its mesh and merges that file. The extra work
over meshing in process is therefore the fork, the write and the read-back.
This script times each of them with Gmsh's Python API on the bundled box at a
size that gives about 1e6 tetrahedra (or --size), and `dtmap run` on the same
scene, and prints the ratio of the extra work to the run's wall time.

Usage: /usr/bin/python3 bench/contain_cost.py DTMAP [--size H]
"""

import json
import os
import subprocess
import sys
import tempfile
import time

import gmsh

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def timed(f):
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


def main():
    dtmap = sys.argv[1]
    size = float(sys.argv[sys.argv.index("--size") + 1]) if "--size" in sys.argv else 1.72e-3
    tmp = tempfile.mkdtemp(prefix="dtmap-contain-")
    geo = os.path.join(SRC, "geometries", "box.geo")
    msh = os.path.join(tmp, "mesh.msh")

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.open(geo)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    t_mesh = timed(lambda: gmsh.model.mesh.generate(3))
    n = sum(len(t) for t in gmsh.model.mesh.getElements(3)[1])
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.option.setNumber("Mesh.SaveAll", 1)
    t_write = timed(lambda: gmsh.write(msh))

    def read_back():
        gmsh.model.mesh.clear()
        gmsh.model.mesh.rebuildNodeCache(False)
        gmsh.merge(msh)

    t_read = timed(read_back)

    def fork_wait():
        pid = os.fork()
        if pid == 0:
            os._exit(0)
        os.waitpid(pid, 0)

    t_fork = timed(fork_wait)
    gmsh.finalize()

    scene = os.path.join(tmp, "box.xml")
    with open(scene, "w") as f:
        f.write("""<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="%s"/>
  <meshing size="%g" order="1" dim="3"/>
  <material name="steel" groups="block" E="210e9" nu="0.3" rho="7850"/>
  <effects><elastic formulation="3d" length="eigen"/></effects>
  <time safety="0.9" duration="1e-4"/>
</dtmap-scene>
""" % (geo, size))
    t0 = time.perf_counter()
    subprocess.run([dtmap, "run", scene, "-q", "-o", os.path.join(tmp, "out.msh"), "--report",
                    os.path.join(tmp, "out.json")], check=True)
    t_run = time.perf_counter() - t0
    elements = json.load(open(os.path.join(tmp, "out.json")))["mesh"]["elements"]
    extra = t_write + t_read + t_fork
    print("| tetrahedra | Gmsh meshing (s) | write .msh (s) | read back (s) | fork (s) | dtmap run (s) | "
          "extra / run |")
    print("|---|---|---|---|---|---|---|")
    print("| %d (run: %d) | %.1f | %.2f | %.2f | %.3f | %.1f | %.1f %% |" %
          (n, elements, t_mesh, t_write, t_read, t_fork, t_run, 100 * extra / t_run))
    for f in os.listdir(tmp):
        os.remove(os.path.join(tmp, f))
    os.rmdir(tmp)


if __name__ == "__main__":
    main()
