"""Readers of solver decks, written from the solvers' manuals and not from
dtmap's writers, for tests/t372-deck-read.py:

- Abaqus-style input (Abaqus Keywords Reference; CalculiX's manual, ch. 7):
  a keyword line starts with '*' and carries comma-separated parameters
  (NAME=VALUE, case-insensitive), data lines are comma-separated, a line
  starting with '**' is a comment.
- LS-DYNA keyword input (Keyword User's Manual, vol. I, "General card
  format"): a keyword starts with '*' in column 1, '$' starts a comment,
  cards are fixed columns (*NODE: I8 then 3 x E16; *ELEMENT_SOLID, _SHELL,
  _BEAM and _MASS: I8 fields, the mass an E16; *DEFINE_CURVE's points
  2 x E20; the others 10 columns), or, when the card holds a comma, free
  format: fields separated by commas, each at most as many characters as
  its fixed columns (a longer one is refused here), a missing one empty;
  the _TITLE option adds a title line before the first card.

Both return a Deck: nodes {id: xyz}, elements {id: (type, nodes, set or
part)}, element sets {name: set of ids}, node sets {name: set of ids},
materials {name: (E, nu, rho)}, sections per set or part, masses {element
id: (node, mass)}, *EQUATION constraints, the step controls and (LS-DYNA)
the curves."""


class Deck:
    def __init__(self):
        self.nodes, self.elements, self.elsets, self.nsets = {}, {}, {}, {}
        self.materials, self.sections, self.masses, self.controls = {}, {}, {}, {}
        self.curves = {}  # LS-DYNA: {lcid: [(abscissa, ordinate)]}
        self.equations = []  # Abaqus-style *EQUATION: [(node, dof, coefficient), ...] each


# ---- Abaqus-style ----

def _keyword(line):
    parts = [p.strip() for p in line[1:].split(",")]
    params = {}
    for p in parts[1:]:
        k, _, v = p.partition("=")
        params[k.strip().upper()] = v.strip()
    return parts[0].upper(), params


def _sections(path, comment, head):
    """(head(keyword line), [data lines]) of a deck: a line starting with
    '*' opens one, lines starting with comment are left out."""
    out = []
    with open(path) as f:
        lines = f.read().split("\n")
    for line in lines:
        if line.startswith(comment):
            continue
        if line.startswith("*"):
            out.append((head(line), []))
        elif out:
            out[-1][1].append(line)
    return out


def _blocks(path):
    """(keyword, params, data lines) of an Abaqus-style file, comments out."""
    return [k + (data,) for k, data in _sections(path, "**", _keyword)]


def _ids(data, elsets):
    ids = set()
    for line in data:
        for tok in (t.strip() for t in line.split(",")):
            if not tok:
                continue
            if tok[0].isdigit():
                ids.add(int(tok))
            else:
                ids |= elsets[tok.upper()]
    return ids


def read_inp(path):
    d = Deck()
    material, pending_mass = None, {}
    for key, par, data in _blocks(path):
        if key == "NODE":
            for line in data:
                v = line.split(",")
                d.nodes[int(v[0])] = tuple(float(x) for x in v[1:4])
        elif key == "ELEMENT":
            name = par["ELSET"].upper()
            ids = set()
            for line in data:
                v = [int(x) for x in line.split(",")]
                d.elements[v[0]] = (par["TYPE"].upper(), v[1:], name)
                ids.add(v[0])
            d.elsets.setdefault(name, set()).update(ids)
        elif key == "ELSET":
            d.elsets.setdefault(par["ELSET"].upper(), set()).update(_ids(data, d.elsets))
        elif key == "NSET":
            d.nsets[par["NSET"].upper()] = _ids(data, {})
        elif key == "MATERIAL":
            material = par["NAME"].upper()
            d.materials[material] = [None, None, None]
        elif key == "ELASTIC":
            e, nu = (float(x) for x in data[0].split(",")[:2])
            d.materials[material][0:2] = [e, nu]
        elif key == "DENSITY":
            d.materials[material][2] = float(data[0].split(",")[0])
        elif key.endswith("SECTION"):
            values = [[float(x) for x in line.split(",") if x.strip()] for line in data if line.strip()]
            d.sections[par["ELSET"].upper()] = (key, par, values)
        elif key == "MASS":
            pending_mass[par["ELSET"].upper()] = float(data[0].split(",")[0])
        elif key == "EQUATION":  # a term count line, then node, dof, coefficient triples
            terms = [x.strip() for x in ",".join(data[1:]).split(",") if x.strip()]
            d.equations.append([(int(terms[k]), int(terms[k + 1]), float(terms[k + 2]))
                                for k in range(0, len(terms), 3)])
        elif key == "DYNAMIC":
            d.controls["dynamic"] = (par, [float(x) for x in data[0].split(",") if x.strip()])
    for name, m in pending_mass.items():
        for eid in d.elsets[name]:
            d.masses[eid] = (d.elements[eid][1][0], m)
    return d


# ---- LS-DYNA ----

def _fields(line, widths):
    if "," in line:  # free format
        out = [t.strip() for t in line.split(",")]
        if len(out) > len(widths):
            raise ValueError("%d fields, the card has %d: %r" % (len(out), len(widths), line))
        for t, w in zip(out, widths):
            if len(t) > w:
                raise ValueError("field %r longer than its %d columns: %r" % (t, w, line))
        return out + [""] * (len(widths) - len(out))
    out, at = [], 0
    for w in widths:
        out.append(line[at:at + w].strip())
        at += w
    return out


def _num(text, kind=float):
    return kind(text) if text else kind(0)


def _cards(path):
    """(keyword, cards) of a keyword file: each card a line, comments out."""
    return _sections(path, "$", lambda line: line[1:].strip().upper())


def _id_cards(cards):
    return [int(x) for c in cards for x in _fields(c, [10] * 8) if x]


def _element(d, key, cards):
    slots = {"ELEMENT_SOLID": 8, "ELEMENT_SHELL": 4, "ELEMENT_BEAM": 2, "ELEMENT_BEAM_ORIENTATION": 2}[key]
    step = 2 if key == "ELEMENT_BEAM_ORIENTATION" else 1
    for k in range(0, len(cards), step):
        v = [int(x) for x in _fields(cards[k], [8] * (2 + slots))]
        nodes = list(dict.fromkeys(v[2:]))  # degenerate forms repeat their last node
        orient = tuple(_num(x) for x in _fields(cards[k + 1], [16] * 3)) if step == 2 else None
        d.elements[v[0]] = (key, nodes, v[1], orient)


def read_k(path):
    d = Deck()
    for key, cards in _cards(path):
        if key == "NODE":
            for c in cards:
                f = _fields(c, [8, 16, 16, 16])
                d.nodes[int(f[0])] = tuple(_num(x) for x in f[1:])
        elif key.startswith("ELEMENT_") and key != "ELEMENT_MASS":
            _element(d, key, cards)
        elif key == "ELEMENT_MASS":
            for c in cards:
                f = _fields(c, [8, 8, 16])
                d.masses[int(f[0])] = (int(f[1]), float(f[2]))
        elif key == "PART":
            f = _fields(cards[1], [10] * 3)
            d.sections.setdefault("parts", {})[int(f[0])] = (cards[0].strip(), int(f[1]), int(f[2]))
        elif key.startswith("SECTION_"):
            f = [_fields(c, [10] * 8) for c in cards[1:]]
            d.sections.setdefault("sections", {})[int(f[0][0])] = (key, cards[0].strip(), f)
        elif key == "MAT_ELASTIC_TITLE":
            f = _fields(cards[1], [10] * 4)
            d.materials[int(f[0])] = (cards[0].strip(), float(f[2]), float(f[3]), float(f[1]))
        elif key == "SET_NODE_LIST_TITLE":
            d.nsets[cards[0].strip()] = set(_id_cards(cards[2:]))
        elif key == "SET_PART_LIST_TITLE":
            d.elsets[cards[0].strip()] = ("parts", set(_id_cards(cards[2:])))
        elif key in ("SET_SOLID_TITLE", "SET_SHELL_LIST_TITLE", "SET_BEAM_TITLE"):
            d.elsets.setdefault(cards[0].strip(), ("elements", set()))[1].update(_id_cards(cards[2:]))
        elif key == "CONTROL_TIMESTEP":
            f = _fields(cards[0], [10] * 8)
            d.controls["tssfac"] = float(f[1])
            d.controls["lctm"] = _num(f[5], int)
        elif key in ("DEFINE_CURVE", "DEFINE_CURVE_TITLE"):
            cards = cards[1:] if key.endswith("_TITLE") else cards
            f = _fields(cards[0], [10] * 8)
            sfa, sfo = _num(f[2]) or 1.0, _num(f[3]) or 1.0  # 0: 1
            points = [tuple(_num(x) for x in _fields(c, [20, 20])) for c in cards[1:]]
            d.curves[int(f[0])] = [(sfa * (a + _num(f[4])), sfo * (o + _num(f[5]))) for a, o in points]  # offsets first
        elif key == "CONTROL_TERMINATION":
            d.controls["endtim"] = float(_fields(cards[0], [10])[0])
    return d
