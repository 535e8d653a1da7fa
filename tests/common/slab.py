"""The thin-layer model the selective-mass tests share (t926, t927, t981):
a steel block 20 x 20 x 10 mm with a layer 0.8 mm thick fused on its top
(OpenCASCADE fragments, one physical volume "block"), whose flat
tetrahedra hold the step down; the shell-and-beam scene that selective
mass scaling refuses; and the tet4s of a .msh read by Gmsh's API."""

import numpy as np

GEO = """SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.02, 0.02, 0.01};
Box(2) = {0, 0, 0.01, 0.02, 0.02, 0.0008};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("block") = {1, 2};
"""

SHELLS = """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="shell_beam_single.geo"/>
<meshing size="1" order="1" dim="2"/>
<material name="steel" groups="plate rod" E="200e9" nu="0.3" rho="7850"/>
<section groups="plate" kind="shell" thickness="0.01"/>
<section groups="rod" kind="beam" radius="0.01"/>
<effects><elastic/></effects>
</dtmap-scene>
"""


def read_tets(msh, name):
    """(xyz [n][3], tets [ne][4] node indices) of the .msh, by Gmsh's API (name: Gmsh's session)."""
    import gmsh
    gmsh.initialize([name, "-v", "0"])
    try:
        gmsh.open(msh)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = {int(t): i for i, t in enumerate(tags)}
        _, conn = gmsh.model.mesh.getElementsByType(4)
        tets = np.array([index[int(t)] for t in conn]).reshape(-1, 4)
        return np.array(coords).reshape(-1, 3), tets
    finally:
        gmsh.finalize()
