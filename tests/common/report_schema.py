"""Validate dtmap reports against schema/dtmap-report.schema.json (JSON
Schema draft 2020-12, with Debian's python3-jsonschema).

    python3 report_schema.py SCHEMA FILE_OR_DIR...

A folder stands for every *.json below it: the test helpers (testutil.c,
testutil.py) run this on their temporary folder as each test program ends,
so every report the suite writes is checked.  NaN and infinities are not
JSON and are refused.  Exit 0 when all are valid, 1 with one line per
problem otherwise.
"""

import json
import os
import sys

import jsonschema


def _refuse_constant(name):
    raise ValueError("%s is not JSON" % name)


def load(path):
    with open(path) as f:
        return json.load(f, parse_constant=_refuse_constant)


def validator(schema_path):
    schema = load(schema_path)
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def problems(v, report):
    """One line per violation: the JSON path and what is wrong."""
    out = []
    for e in sorted(v.iter_errors(report), key=lambda e: list(e.absolute_path)):
        where = "/".join(str(p) for p in e.absolute_path) or "(top)"
        out.append("%s: %s" % (where, e.message))
    return out


def reports(paths):
    for p in paths:
        if os.path.isdir(p):
            for root, _, files in os.walk(p):
                for f in sorted(files):
                    if f.endswith(".json"):
                        yield os.path.join(root, f)
        else:
            yield p


def main(argv):
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    v = validator(argv[1])
    bad = 0
    for path in reports(argv[2:]):
        try:
            found = problems(v, load(path))
        except ValueError as e:
            found = ["not valid JSON: %s" % e]
        for line in found:
            print("%s: %s" % (path, line))
        bad += bool(found)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
