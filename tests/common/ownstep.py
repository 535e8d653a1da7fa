"""Each element's own safe step from a dtmap .msh, read with Gmsh's API: the
safety x the larger of its element step (the 'dt' view) and the smallest
nodal bound at its nodes (the 'nodal dt' view), for a scene with one effect
(with several, dtmap takes the smallest of this over the effects' own
views). What "below the target" counts (issue 43, item 4)."""

import gmsh

import testutil as tu


def own_safe_steps(msh, safety):
    """{element tag: safety x max(dt, min nodal dt over its nodes)}."""
    dt, nodal = tu.view_values(msh, "dt"), tu.view_values(msh, "nodal dt")
    gmsh.initialize(["ownstep", "-v", "0"])
    try:
        gmsh.open(msh)
        conn = {}
        for et in gmsh.model.mesh.getElementTypes():
            tags, nodes = gmsh.model.mesh.getElementsByType(et)
            nn = len(nodes) // len(tags) if len(tags) else 0
            for k, t in enumerate(tags):
                conn[int(t)] = [int(n) for n in nodes[k * nn:(k + 1) * nn]]
    finally:
        gmsh.finalize()
    return {t: safety * max(v, min(nodal[n] for n in conn[t] if n in nodal)) for t, v in dt.items()}
