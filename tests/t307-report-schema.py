"""The report's JSON Schema (schema/dtmap-report.schema.json) is a valid
draft 2020-12 schema that documents every field with its unit, accepts a
real report (the bundled plate with --posterior: global estimate, Lanczos
details, subcycling, mass scaling, the advice), a real report whose global
estimate rests on the probable bound (the bundled box, 2,293 nodes: its
factorisation is too dear; the bound's eps is checked against its closed
form (ln(1.648 sqrt(n) / 1e-12) / (2k - 1))^2 to 1e-12 relative and must
meet 1 - safety^2) and a real `verify
--report` (its own document in the same schema), and catches mistakes: a
missing required field, a field nobody documented, a wrong type, a
non-integer count, a negative or zero step, an unknown basis, an element
without its step, a report that does not say its units, and NaN (which
is not JSON). Every report the suite writes is also
checked against it as each test program ends (testutil.c, testutil.py)."""

import copy
import json
import math
import os
import re

import report_schema
import testutil as tu

SCHEMA = os.path.join(tu.SRC, "schema", "dtmap-report.schema.json")
# A unit after a comma or in parentheses (", s", "(kg/m in 2D)", ", %", ", rad/s", ", m^2", ", h", ", Hz"),
# or "dimensionless".
UNIT = re.compile(r"([,(] ?(s|m|m\^2|m\^4|kg|kg/m|%|1/s\^2|1/s|rad/s|m/s|degrees|h|Hz)([ ),]|$))|dimensionless")


def resolve(prop, defs):
    return resolve(defs[prop["$ref"].split("/")[-1]], defs) if "$ref" in prop else prop


def real_valued(prop, defs):
    """True when the property holds real numbers (directly, through $ref or
    as array items); integers are counts or tags and carry no unit."""
    p = resolve(prop, defs)
    return p.get("type") == "number" or (p.get("type") == "array" and real_valued(p.get("items", {}), defs))


def properties(node, where=""):
    """Every (path, property schema) of the schema, recursively."""
    for name, prop in node.get("properties", {}).items():
        yield where + "/" + name, prop
        yield from properties(prop, where + "/" + name)
        yield from properties(prop.get("items", {}), where + "/" + name + "[]")
    for name, d in node.get("$defs", {}).items():
        yield from properties(d, "$defs/" + name)


class Schema(tu.unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.v = report_schema.validator(SCHEMA)
        scene = os.path.join(tu.SRC, "geometries", "plate_with_hole.xml")
        code, out = tu.run("run", scene, "-q", "--posterior", "--solver-rule", "calculix,lsdyna", "-o", "plate_dt.msh",
                           "--report", "plate.json")
        assert code == 0, out
        cls.report = tu.report("plate.json")
        code, out = tu.run("verify", scene, "-q", "--steps", "200", "--report", "plate_verify.json")
        assert code == 0, out
        cls.verify = tu.report("plate_verify.json")
        box = os.path.join(tu.SRC, "geometries", "box.xml")
        # a budget of one flop makes the factorisation too dear (src/analysis/global.c), so that the
        # box's step rests on the probable bound, whose fields are checked below
        os.environ["DTMAP_BENCH_CERT_BUDGET"] = "1"
        try:
            code, out = tu.run("run", box, "-q", "--posterior", "-o", "box_dt.msh", "--report", "box.json")
        finally:
            del os.environ["DTMAP_BENCH_CERT_BUDGET"]
        assert code == 0, out
        cls.box = tu.report("box.json")

    def test_every_field_documented_with_its_unit(self):
        schema = report_schema.load(SCHEMA)
        defs = schema["$defs"]
        count = 0
        for where, prop in properties(schema):
            text = prop.get("description") or resolve(prop, defs).get("description")
            self.assertTrue(text, where + " has no description")
            if real_valued(prop, defs):
                self.assertRegex(text, UNIT, where + ": the description names no unit")
            count += 1
        self.assertGreater(count, 60)

    def test_real_report_is_valid(self):
        self.assertEqual(report_schema.problems(self.v, self.report), [])
        for key in ("subcycling", "mass_scaling", "model"):
            self.assertIn(key, self.report)
        self.assertGreater(self.report["model"]["mass"], 0)
        self.assertEqual(self.report["model"]["units"], "SI")
        self.assertEqual(self.report["units"], {"system": "SI", "report": "SI", "model": "SI"})
        self.assertIn("lanczos", self.report["effect_minima"][0])
        self.assertEqual(self.report["dt"]["basis"], "global estimate")
        self.assertEqual([x["solver"] for x in self.report["solvers"]], ["calculix", "lsdyna"])
        self.assertIsNone(self.report["solvers"][1]["hours"])  # LS-DYNA's cost is not known here

    def test_probable_report(self):
        self.assertEqual(report_schema.problems(self.v, self.box), [])
        lz = self.box["effect_minima"][0]["lanczos"]
        self.assertEqual(lz["certificate"], "probable")
        self.assertEqual(lz["deterministic"], "too dear")
        self.assertEqual(lz["seed"], 20261121)
        pb, safety = lz["probable"], self.box["dt"]["safety"]
        self.assertEqual(pb["failure"], 1e-12)
        self.assertEqual(pb["steps"], lz["iterations"])
        eps = (math.log(1.648 * math.sqrt(pb["n"]) / 1e-12) / (2 * pb["steps"] - 1)) ** 2
        self.assertAlmostEqual(pb["eps"] / eps, 1, delta=1e-12)
        self.assertLessEqual(pb["eps"], 1 - safety ** 2)
        # the step of theta / (1 - eps): sqrt(1 - eps) x the step of theta (no damping here; 1e-9 for
        # the rounding allowance 10 k eps |T| on theta)
        self.assertAlmostEqual(pb["dt_certified"] / (lz["dt_bracket"][1] * math.sqrt(1 - pb["eps"])), 1, delta=1e-9)
        dt = self.box["dt"]
        self.assertEqual(dt["recommended"], min(safety * dt["basis_step"], pb["dt_certified"]))
        self.assertEqual(dt["recommended_certified"], pb["dt_certified"] < safety * dt["basis_step"])
        r = copy.deepcopy(self.box)
        for what, change in {"eps of 1": lambda p: p.update(eps=1.0), "no certified step": lambda p: p.pop("dt_certified"),
                             "undocumented field": lambda p: p.update(delta=1)}.items():
            r = copy.deepcopy(self.box)
            change(r["effect_minima"][0]["lanczos"]["probable"])
            self.assertNotEqual(report_schema.problems(self.v, r), [], what)
        r["effect_minima"][0]["lanczos"]["certificate"] = "likely"
        self.assertNotEqual(report_schema.problems(self.v, r), [], "unknown certificate")

    def mutated(self, change):
        r = copy.deepcopy(self.report)
        change(r)
        return report_schema.problems(self.v, r)

    def test_mistakes_are_caught(self):
        mistakes = {
            "missing dt.recommended": lambda r: r["dt"].pop("recommended"),
            "missing timings": lambda r: r.pop("timings"),
            "undocumented top-level field": lambda r: r.update(costs={"element_steps": 1}),
            "undocumented dt field": lambda r: r["dt"].update(recommend=1e-7),
            "step as a string": lambda r: r["dt"].update(min="1e-7"),
            "negative step": lambda r: r["dt"].update(recommended=-1e-7),
            "zero step": lambda r: r["effect_minima"][0].update(min=0),
            "unknown basis": lambda r: r["dt"].update(basis="guess"),
            "fractional count": lambda r: r["mesh"].update(elements=10.5),
            "no threads": lambda r: r["timings"].update(threads=0),
            "safety above 1": lambda r: r["dt"].update(safety=1.5),
            "centroid of 2 coordinates": lambda r: r["dt"].update(centroid=[0, 0]),
            "element without its step": lambda r: r["effect_minima"][0].pop("min"),
            "speed-up below 1": lambda r: r["subcycling"].update(speedup=0.5),
            "level count negative": lambda r: r["subcycling"]["levels"].append(-1),
            "lanczos field missing": lambda r: r["effect_minima"][0]["lanczos"].pop("converged"),
            "NaN as null": lambda r: r["dt"].update(nodal=None),
            "cost without its basis": lambda r: r["cost"].pop("basis"),
            "undocumented field of a worst element": lambda r: r["worst"].append({"element": 1, "type": "tri3", "group": "a", "dt": 1e-7,
                                                          "length": 1e-3, "effect": "elastic", "remedy": "x"}),
            "warning not a sentence": lambda r: r["warnings"].append(""),
            "refine rounds as a list": lambda r: r.update(refine=[{"round": 0}]),
            "model without its units": lambda r: r["model"].pop("units"),
            "report without its units": lambda r: r.pop("units"),
            "report fields said to be in mm-t-s": lambda r: r["units"].update(report="mm-t-s"),
            "unknown system of units": lambda r: r["units"].update(system="cgs"),
            "negative model mass": lambda r: r["model"].update(mass=-1.0),
            "bounding box of 2 coordinates": lambda r: r["model"]["bbox"].update(min=[0, 0]),
            "solver run without its hours": lambda r: r["solvers"][0].pop("hours"),
            "unknown solver": lambda r: r["solvers"][0].update(solver="nastran"),
            "solver step zero": lambda r: r["solvers"][1].update(step=0),
        }
        for what, change in mistakes.items():
            self.assertNotEqual(self.mutated(change), [], what)

    def test_verify_report(self):
        self.assertEqual(report_schema.problems(self.v, self.verify), [])
        self.assertEqual(self.verify["step"], self.verify["recommended"])  # no --factor: exactly the recommended step
        self.assertEqual(self.verify["verdict"], "stable")
        self.assertEqual(self.verify["units"]["report"], "SI")
        for change in (lambda r: r.pop("steps"), lambda r: r.update(verdict="fine"), lambda r: r.update(cost={}),
                       lambda r: r["effects"][0].pop("growth")):
            r = copy.deepcopy(self.verify)
            change(r)
            self.assertNotEqual(report_schema.problems(self.v, r), [])

    def test_nan_is_refused(self):
        text = json.dumps(self.report).replace('"safety": 0.9', '"safety": NaN')
        self.assertIn("NaN", text)
        path = tu.write("nan.txt", text)  # not *.json: the end-of-script check would refuse it too
        with self.assertRaises(ValueError):
            report_schema.load(path)


if __name__ == "__main__":
    tu.main()
