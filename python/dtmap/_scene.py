"""A dtmap scene written from Python values, for :func:`dtmap.analyse`.

The scene's source is ``<model/>``: the current Gmsh model of the script.
Materials are a dict ``name -> properties``, sections a list of dicts of
``<section>`` attributes (``{"groups": "rebar", "kind": "truss", "area":
3.1e-4}``) and effects a list of names,
``(name, attributes)`` pairs or dicts with a ``"name"`` key; attribute
names may use ``_`` for ``-`` (``heat_capacity`` for ``heat-capacity``).
An effect with a ``library`` attribute is an external one
(``<effect name=... library=...>``).  The text is validated by libdtmap
against the scene schema like a file, so mistakes come back with the line
of the generated text, which :func:`annotate` appends to the message (with
the ``sections=`` entry for a ``<section>`` a message asks for).
"""

import re
from xml.sax.saxutils import quoteattr

NAME = "dtmap.analyse.xml"  # how messages name a generated scene; relative paths resolve in the working folder


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)  # shortest text that reads back to the same double
    if isinstance(v, (list, tuple)):
        return " ".join(str(x) for x in v)
    return str(v)


def _attributes(d):
    return "".join(" %s=%s" % (k.replace("_", "-"), quoteattr(_value(v))) for k, v in d.items())


def _effect(e):
    if isinstance(e, str):
        name, attrs = e, {}
    elif isinstance(e, dict):
        attrs = dict(e)
        name = attrs.pop("name")
    else:
        name, attrs = e
        attrs = dict(attrs)
    if "library" in attrs:
        return "    <effect name=%s%s/>" % (quoteattr(name), _attributes(attrs))
    return "    <%s%s/>" % (name, _attributes(attrs))


def _sections(sections):
    """<section> lines from a list of dicts of the scene's attributes (or one dict)."""
    if isinstance(sections, dict):
        sections = [sections]
    for s in sections:
        if not isinstance(s, dict) or "kind" not in s:
            raise ValueError("dtmap.analyse: sections= takes dicts of <section> attributes, e.g. "
                             "[{'groups': 'rebar', 'kind': 'truss', 'area': 3.1e-4}]; got %r" % (s,))
        yield "  <section%s/>" % _attributes(s)


def scene_text(materials, effects, time=None, meshing=None, sections=None):
    """The XML of a scene on the current Gmsh model."""
    if not materials:
        raise ValueError("dtmap.analyse: give materials={name: {property: value, ...}} or scene=")
    if not effects:
        raise ValueError("dtmap.analyse: give effects=[...] (e.g. ['elastic']) or scene=")
    lines = ['<dtmap-scene version="1">', "  <model/>"]
    if meshing:
        lines.append("  <meshing%s/>" % _attributes(meshing))
    for name, props in materials.items():
        lines.append("  <material name=%s%s/>" % (quoteattr(name), _attributes(props)))
    lines.extend(_sections(sections or []))
    lines.append("  <effects>")
    lines.extend(_effect(e) for e in effects)
    lines.append("  </effects>")
    if time:
        lines.append("  <time%s/>" % _attributes(time))
    lines.append("</dtmap-scene>")
    return "\n".join(lines) + "\n"


def _python_section(xml):
    """The sections= entry that writes the <section .../> element xml."""
    attrs = re.findall(r'([\w-]+)="([^"]*)"', xml)
    items = []
    for k, v in attrs:
        try:
            value = repr(float(v)) if v != "..." else "..."
        except ValueError:
            value = repr(v)
        items.append("%r: %s" % (k.replace("-", "_"), value))
    return "{%s}" % ", ".join(items)


def annotate(message, text):
    """Append the generated line a message points at ("dtmap.analyse.xml:N: ..."), and
    the sections= entry for a <section> element the message asks for."""
    m = re.match(re.escape(NAME) + r":(\d+):", message)
    lines = text.split("\n")
    if m and 1 <= int(m.group(1)) <= len(lines):
        message = "%s\n  (line %s of the generated scene: %s)" % (message, m.group(1),
                                                                   lines[int(m.group(1)) - 1].strip())
    sections = [_python_section(x) for x in re.findall(r"<section [^>]*/>", message)]
    if sections:
        message += "\n  (from Python: dtmap.analyse(..., sections=[%s]))" % ", ".join(sections)
    return message
