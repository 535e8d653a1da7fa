#!/usr/bin/python3
"""Check (not a test): the views of two dtmap outputs of the same mesh,
element by element, e.g. a build before a kernel change against one after
it. Prints, for every view both files hold, the number of values and the
largest relative difference; exits 1 when one exceeds the tolerance
(default 1e-12, what issue 46 allows the dt map to move).

Usage: compare_views.py BEFORE.msh AFTER.msh [tolerance]
"""
import sys

import gmsh
import numpy as np


def views(path):
    """{name: {tag: value}} of the file's views (the last of each name)."""
    gmsh.initialize(["compare", "-v", "0"])
    gmsh.open(path)
    out = {}
    for i, tag in enumerate(gmsh.view.getTags()):
        name = gmsh.option.getString(f"View[{i}].Name")
        kind, tags, data, _, _ = gmsh.view.getModelData(tag, 0)
        out[name] = dict(zip(tags, (d[0] for d in data)))
    gmsh.finalize()
    return out


def main():
    a, b = views(sys.argv[1]), views(sys.argv[2])
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-12
    worst = 0.0
    for name in sorted(set(a) & set(b)):
        keys = sorted(set(a[name]) & set(b[name]))
        x = np.array([a[name][k] for k in keys], dtype=float)
        y = np.array([b[name][k] for k in keys], dtype=float)
        same = (x == y) | (np.isnan(x) & np.isnan(y))
        scale = np.maximum(np.abs(x), np.abs(y))
        rel = np.where(same, 0.0, np.abs(x - y) / np.where(scale > 0, scale, 1))
        r = float(rel.max()) if len(rel) else 0.0
        worst = max(worst, r)
        print(f"{name}: {len(keys)} values ({len(a[name])} / {len(b[name])}), largest relative difference {r:.3g}")
    print(f"largest relative difference {worst:.3g} (tolerance {tol:g})")
    sys.exit(0 if worst <= tol else 1)


if __name__ == "__main__":
    main()
