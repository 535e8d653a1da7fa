"""Counts of one or more tables of bench/refine_survey.sh (markdown, one row
per model): models usable (run did not refuse them), met (and how: by the
input, by a remesh, with point masses), not met by cause, and rounds.
Usage: refine_survey_counts.py TABLE.md [TABLE.md ...]"""

import collections
import sys


def rows(path):
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 7 or cells[0] in ("model", "---") or cells[0].startswith("-"):
            continue
        yield cells


for path in sys.argv[1:]:
    usable = met = 0
    how, causes, rounds = collections.Counter(), collections.Counter(), collections.Counter()
    for model, outcome, met_by, cause, cost, nrounds, mass in rows(path):
        if outcome.startswith("run exit") or outcome.startswith("exit 2") or outcome.startswith("exit 3"):
            continue
        usable += 1
        if outcome == "met":
            met += 1
            how[met_by] += 1
            rounds[nrounds] += 1
        else:
            causes[cause] += 1
    print("%s: %d usable, %d met (%s; remeshes %s), not met: %s" % (
        path, usable, met, ", ".join("%s %d" % kv for kv in sorted(how.items())),
        ", ".join("%s: %d" % kv for kv in sorted(rounds.items())),
        ", ".join("%s %d" % kv for kv in causes.most_common())))
