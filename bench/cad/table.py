"""Tables of the real-CAD survey (bench/cad/survey.py's results) for
docs/cad-corpus.md: counts per configuration (parts, met and of them met by
the input, true stops, wrong stops, crashes; the kept mesh's cost over the
input's for those met by a remesh, that of the uniform mesh that shows a
stop wrong), then a row per part.

A configuration's counts are over the parts it has a result for; a part
whose input Gmsh or dtmap cannot mesh is counted apart ("no input").

Usage: table.py OUT_DIR   (bench/cad/survey.sh's CAD_OUT)
"""

import os

from survey import load  # the same reader of a result file (None when missing or torn)
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIGS = ["1.5-default", "1.3-default", "1.5-posterior", "1.3-posterior"]


def kinds():
    out = {}
    for line in open(os.path.join(HERE, "parts.tsv"), encoding="utf-8"):
        if not line.startswith("#") and line.strip():
            c = line.split("\t")
            out[c[0]] = c[1]
    return out


def spread(xs):
    if not xs:
        return ""
    xs = sorted(xs)
    if len(xs) == 1:
        return "%.2f" % xs[0]
    return "%.2f-%.2f (median %.2f)" % (xs[0], xs[-1], statistics.median(xs))


def cell(r):
    if r is None:
        return ""
    o = r["outcome"]
    causes = ", ".join(r.get("causes") or []) or "no cause"
    if o == "met":
        if r.get("met_by") == "input":
            return "met by the input"
        if "cost_ratio" not in r:
            return "met (no cost in the report)"
        return "met x%.2f (%d remesh)" % (r["cost_ratio"], r.get("remeshes", 0))
    if o == "stop":
        if r.get("wrong"):
            return "**wrong stop**: %s; uniform x%g meets at x%.2f" % (causes, r["uniform_factor"], r["uniform_cost_ratio"])
        return "stop: %s" % causes
    if o == "refused":
        return "exit 2"
    return "**crash**: %s" % r["rc"]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    kind = kinds()
    parts = [p for p in kind if os.path.isdir(os.path.join(out, p))]
    res = {(p, c): load(os.path.join(out, p, c + ".json")) for p in parts for c in CONFIGS}
    inputs = {p: load(os.path.join(out, p, "input.json")) for p in parts}
    no_input = [p for p in parts if inputs[p] and inputs[p]["rc"] != 0]
    run = [c for c in CONFIGS if any(res[(p, c)] for p in parts)]
    print("| configuration | parts | met (by the input) | true stops | wrong stops | crashes | exit 2 |"
          " met by a remesh: kept cost / input | wrong stops: uniform cost / input |")
    print("|---|---|---|---|---|---|---|---|---|")
    for c in run:
        rs = [res[(p, c)] for p in parts if res[(p, c)]]
        met = [r for r in rs if r["outcome"] == "met"]
        stops = [r for r in rs if r["outcome"] == "stop"]
        wrong = [r for r in stops if r.get("wrong")]
        by_input = [r for r in met if r.get("met_by") == "input"]
        print("| %s | %d | %d (%d) | %d | %d | %d | %d | %s | %s |" % (
            c, len(rs), len(met), len(by_input), len(stops) - len(wrong), len(wrong),
            sum(1 for r in rs if r["outcome"] == "crash"), sum(1 for r in rs if r["outcome"] == "refused"),
            spread([r["cost_ratio"] for r in met if "cost_ratio" in r and r.get("met_by") != "input"]),
            spread([r["uniform_cost_ratio"] for r in wrong])))
    print()
    if no_input:
        print("No input mesh (`dtmap run` exit code): %s." % ", ".join(
            "%s (%s)" % (p, inputs[p]["rc"]) for p in no_input))
        print()
    print("| part | kind | input tets | " + " | ".join(run) + " |")
    print("|---|---|---|" + "---|" * len(run))
    for p in parts:
        inp = inputs[p]
        tets = inp.get("elements", "") if inp else ""
        print("| %s | %s | %s | %s |" % (p, kind[p], tets, " | ".join(cell(res[(p, c)]) for c in run)))


if __name__ == "__main__":
    main()
