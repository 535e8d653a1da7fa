"""The one change bench/ccx_fixed_inc.sh makes to CalculiX's nonlingeo.c.

Every place where the explicit increment is selected ends in the same two
statements, dtheta=(*tinc)/(*tper); then dthetaref=dtheta;, right after a
choice between the Courant estimate (or the contact one), the maximum and the
minimum increment (dtset). Before each of those, *tinc takes CCX_FIXED_INC
when that variable is set; nothing else changes. The implicit branch's first
selection (no dtset before it) is left alone. The file is checked to hold
exactly the three explicit selections of CalculiX 2.20 (Debian's
calculix-ccx 2.20-1); another version stops the build with a message.

Usage: python3 bench/ccx_fixed_inc_patch.py PATH/nonlingeo.c
"""
import re
import sys

FIXED = 'if(getenv("CCX_FIXED_INC")) *tinc=atof(getenv("CCX_FIXED_INC"));'
SELECT = re.compile(r"\n([ \t]*)dtheta=\(\*tinc\)/\(\*tper\);\n[ \t]*dthetaref=dtheta;")


def patch(text):
    """The text with the override before each explicit selection."""
    out, last, count = [], 0, 0
    for m in SELECT.finditer(text):
        before = text[max(0, m.start() - 400):m.start()]
        if "dtset" not in before:
            continue
        out.append(text[last:m.start()])
        out.append("\n" + m.group(1) + FIXED)
        last = m.start()
        count += 1
    out.append(text[last:])
    return "".join(out), count


def main():
    path = sys.argv[1]
    with open(path) as f:
        text = f.read()
    if FIXED in text:
        sys.exit(f"{path}: already patched")
    new, count = patch(text)
    if count != 3:
        sys.exit(f"{path}: {count} explicit increment selections found, 3 expected "
                 "(not CalculiX 2.20 as Debian ships it)")
    with open(path, "w") as f:
        f.write(new)
    print(f"{path}: CCX_FIXED_INC at {count} increment selections")


if __name__ == "__main__":
    main()
