"""The scene attributes the documents name are the ones the scene reader
takes (issue 43 item 7: docs/deck.md named a section attribute `shear`;
the reader takes `shear-factor`).

The reference is the scene's XML Schema as the build generates it
(generated/dtmap-scene.xsd beside the CLI, from schema/dtmap-scene.xsd.in
and the effects' declarations), which the reader validates every scene
against. In README.md and docs/*.md:
- every scene tag written in backticks or in a fenced block
  (`<section kind="shell" thickness="0.01"/>`, `<time f-max>`,
  `<meshing size=h>`) names only attributes its element declares
  (elements that take any attribute, `<effect>`, are the core's to check);
- a bare attribute a sentence names ("the section gives `X`", "attribute
  `X`") is an attribute of some scene element.
"""

import glob
import os
import re
import unittest
import xml.etree.ElementTree as ET

import testutil as tu

XS = "{http://www.w3.org/2001/XMLSchema}"


def schema():
    """{element name: set of attribute names, or None when any attribute is taken}."""
    path = os.path.join(os.path.dirname(os.path.abspath(tu.CLI)), "generated", "dtmap-scene.xsd")
    root = ET.parse(path).getroot()
    types = {}
    for ct in root.iter(XS + "complexType"):
        attrs = {a.get("name") for a in ct.findall(XS + "attribute")}
        any_attr = ct.find(XS + "anyAttribute") is not None
        if ct.get("name"):
            types[ct.get("name")] = None if any_attr else attrs
    elements = {}
    for el in root.iter(XS + "element"):
        name = el.get("name")
        if el.get("type") in types:
            elements[name] = types[el.get("type")]
        elif el.find(XS + "complexType") is not None:
            inline = el.find(XS + "complexType")
            elements[name] = {a.get("name") for a in inline.findall(XS + "attribute")}
    return elements


def documents():
    return [os.path.join(tu.SRC, "README.md")] + sorted(glob.glob(os.path.join(tu.SRC, "docs", "*.md")))


TAG = re.compile(r"<([a-z][a-z0-9-]*)((?:\s+[^<>]*?)?)/?>")
ATTR = re.compile(r"(?:^|\s)([a-z][a-z0-9-]*)(?==|\s|$)")
NAMED = re.compile(r"\b(?:gives|attribute|attributes) `([a-z][a-z0-9-]*)`")


def tags_of(text):
    """Each (line, tag, attribute names) of the scene-like tags in code spans and fenced blocks."""
    fenced, out = False, []
    for n, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        spans = [line] if fenced else re.findall(r"`([^`]*)`", line)
        for span in spans:
            for m in TAG.finditer(span):
                rest = re.sub(r'"[^"]*"|\'[^\']*\'|\.\.\.', " ", m.group(2))
                rest = re.sub(r"=\S*", "= ", rest)
                out.append((n, m.group(1), ATTR.findall(rest)))
    return out


class DocsAttributes(unittest.TestCase):
    def test_tags_name_declared_attributes(self):
        elements = schema()
        self.assertIn("shear-factor", elements["section"])
        every = set().union(*(a for a in elements.values() if a))
        bad, checked = [], 0
        for doc in documents():
            with open(doc) as f:
                text = f.read()
            rel = os.path.relpath(doc, tu.SRC)
            for n, tag, attrs in tags_of(text):
                if tag not in elements or elements[tag] is None:
                    continue
                checked += 1
                bad += ["%s:%d: <%s %s>: %s takes no attribute %s" % (rel, n, tag, " ".join(attrs), tag, a)
                        for a in attrs if a not in elements[tag]]
            for n, line in enumerate(text.splitlines(), 1):
                bad += ["%s:%d: names an attribute `%s` no scene element takes" % (rel, n, a)
                        for a in NAMED.findall(line) if a not in every]
        print("%d scene tags checked in %d documents" % (checked, len(documents())))
        self.assertGreater(checked, 20)
        self.assertEqual(bad, [], "\n".join(bad))


if __name__ == "__main__":
    tu.main()
