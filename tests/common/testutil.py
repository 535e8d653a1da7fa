"""Helpers of the Python test scripts (tests/tNNN-*.py), the counterpart of
testutil.c: the source tree and the dtmap CLI from the command line, a
temporary folder removed at the end, running the CLI, reading reports, and
unittest's runner.  As in the C tests, every *.json the script leaves in its
temporary folder is checked against schema/dtmap-report.schema.json at the
end, and a report that does not follow it fails the script."""

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

SRC = sys.argv[1] if len(sys.argv) > 1 else "."
CLI = sys.argv[2] if len(sys.argv) > 2 else "dtmap"
# The CLI runs under ASan and UBSan (scripts/test.sh's second build): a
# script may then skip repetitions of a path it has already driven once,
# whose numbers the optimised build checks in full.
SANITIZED = os.environ.get("DTM_TEST_SANITIZED") == "1"
_tmp = None


def tmpdir():
    """This script's temporary folder (created on first use)."""
    global _tmp
    if _tmp is None:
        _tmp = tempfile.mkdtemp(prefix="dtmap-pytest-")
    return _tmp


def path(name):
    return os.path.join(tmpdir(), name)


def write(name, text):
    with open(path(name), "w") as f:
        f.write(text)
    return path(name)


def elastic_scene(name, geo, dim, material='groups="block"', time='duration="1e-4"'):
    """NAME.xml: GEO meshed in dim, steel (material: its groups or default
    attribute), the elastic effect (3D, or plane stress in 2D), <time TIME/>."""
    return write(name + ".xml", """<?xml version="1.0"?>
<dtmap-scene version="1">
<geometry file="%s"/>
<meshing dim="%d"/>
<material name="steel" %s E="210e9" nu="0.3" rho="7850"/>
<effects><elastic formulation="%s"/></effects>
<time %s/>
</dtmap-scene>
""" % (geo, dim, material, "3d" if dim == 3 else "plane-stress", time))


def plain_env(**extra):
    """The environment for programs that are not dtmap's (man, bash): without
    the sanitizer runtimes a sanitizer build preloads into python3."""
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    env.update(extra)
    return env


def run(*args, cwd=None):
    """Run the dtmap CLI; returns (exit code, stdout + stderr)."""
    p = subprocess.run([CLI] + [str(a) for a in args], cwd=cwd or tmpdir(), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, universal_newlines=True)
    return p.returncode, p.stdout


def effect_api_version():
    """DTM_EFFECT_API_VERSION of include/dtmap/effect.h."""
    with open(os.path.join(SRC, "include", "dtmap", "effect.h")) as f:
        return int(re.search(r"#define DTM_EFFECT_API_VERSION (\d+)", f.read()).group(1))


def views(path):
    """{view name: {element or node tag: first value}} of every view of the .msh at path (the
    first view of a name when two share it), read with Gmsh's Python API (imported here: not
    every script needs it)."""
    import gmsh
    gmsh.initialize(["testutil", "-v", "0"])
    try:
        gmsh.open(path)
        out = {}
        for tag in gmsh.view.getTags():
            name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(tag))
            if name not in out:
                _, tags, data, _, _ = gmsh.view.getModelData(tag, 0)
                out[name] = {int(t): float(d[0]) for t, d in zip(tags, data)}
        return out
    finally:
        gmsh.finalize()


def view_values(path, name):
    """{element or node tag: first value} of the view called name in the .msh at path ({} when
    it has none)."""
    return views(path).get(name, {})


def report(name):
    with open(path(name) if not os.path.isabs(name) else name) as f:
        return json.load(f)


def run_dt(name, *extra):
    """`dtmap run NAME.xml` into NAME_dt.msh and NAME_dt.json; its "dt" object."""
    code, log = run("run", name + ".xml", "-q", "-o", name + "_dt.msh", "--report", name + "_dt.json", *extra)
    assert code == 0, log
    return report(name + "_dt.json")["dt"]


def refine(name, target, *extra):
    """`dtmap refine NAME.xml --target T` into NAME_r.msh and NAME_r.json:
    (exit code, output, report)."""
    code, log = run("refine", name + ".xml", "--target", "%.9e" % target, "-o", name + "_r.msh",
                    "--report", name + "_r.json", *extra)
    return code, log, report(name + "_r.json")


def _check_reports():
    if _tmp is None:
        return 0
    checker = os.path.join(SRC, "tests", "common", "report_schema.py")
    schema = os.path.join(SRC, "schema", "dtmap-report.schema.json")
    code = subprocess.call([sys.executable, checker, schema, _tmp])
    if code:
        print("a report written by this test does not follow schema/dtmap-report.schema.json (above)")
    return code


def main():
    """Run the script's unittest cases, then check its reports; exit 1 on any failure."""
    result = unittest.main(argv=[sys.argv[0]], exit=False).result
    bad = _check_reports()
    if _tmp is not None:
        shutil.rmtree(_tmp, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() and not bad else 1)


def histogram(log):
    """([(lo, hi, count)] of the summary's histogram of element steps, its
    title line): the rows under the line "dt in multiples of the ..."."""
    lines = log.splitlines()
    i = next(k for k, l in enumerate(lines) if l.startswith("dt in multiples of the"))
    rows = []
    for l in lines[i + 1:]:
        m = re.match(r"\s+\[([0-9.e+-]+), ([0-9.e+-]+|inf)\)\s+(\d+)", l)
        if not m:
            break
        rows.append((float(m.group(1)), float(m.group(2)), int(m.group(3))))
    return lines[i], rows

