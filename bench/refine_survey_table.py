"""Join the tables of bench/refine_survey.sh's four modes into the one table
of docs/refine-survey.md: a row per model, a cell per mode with how the
target was met (input, mesh with its remeshes and cost ratio, mesh + mass
with its share) or the cause named, then the counts of each mode.
Usage: refine_survey_table.py BOUND.md POSTERIOR.md GLOBAL.md GLOBAL_MASS.md"""

import collections
import sys


def rows(path):
    out = collections.OrderedDict()
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 7 or cells[0] in ("model",) or set(cells[0]) <= set("-"):
            continue
        out[cells[0]] = cells[1:]
    return out


def cell(c):
    if c is None:
        return ""
    outcome, met_by, cause, cost, rounds, mass = c[:6]
    if outcome.startswith("run exit"):
        return "run refused"
    if outcome == "met":
        if met_by == "input":
            return "met by the input"
        if met_by == "mesh and point masses":
            on = "input" if rounds == "0" else "mesh of %s remesh(es)" % rounds
            return "%s + %s %% mass, cost x%s" % (on, mass, cost)
        return "met, %s remesh(es), cost x%s" % (rounds, cost)
    need = "; point masses need %s %%" % mass.split()[1] if mass.startswith("needs") else ""
    return "%s: %s (%s remesh(es))%s" % (outcome, cause, rounds, need)


def counts(table):
    usable = [c for c in table.values() if not c[0].startswith("run exit") and c[0] not in ("exit 2", "exit 3")]
    met = collections.Counter(c[1] for c in usable if c[0] == "met")
    causes = collections.Counter(c[2] for c in usable if c[0] != "met")
    return len(usable), met, causes


def main():
    names = ["bound", "posterior", "global", "global + mass 2 %"]
    tables = [rows(p) for p in sys.argv[1:5]]
    models = list(tables[0].keys())
    print("| model | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for m in models:
        print("| %s | %s |" % (m, " | ".join(cell(t.get(m)) for t in tables)))
    print()
    print("| survey | usable | met | by the input | by a remesh | by mesh + mass (of them on the input) | not met: causes |")
    print("|---|---|---|---|---|---|---|")
    for name, t in zip(names, tables):
        usable, met, causes = counts(t)
        on_input = sum(1 for c in t.values() if c[0] == "met" and c[1] == "mesh and point masses" and c[4] == "0")
        print("| %s | %d | %d | %d | %d | %d (%d) | %s |" % (
            name, usable, sum(met.values()), met["input"], met["mesh"], met["mesh and point masses"], on_input,
            ", ".join("%s %d" % kv for kv in causes.most_common())))


if __name__ == "__main__":
    main()
