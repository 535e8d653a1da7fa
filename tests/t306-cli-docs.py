"""The command's documentation agrees with itself: the man page the build
generated (doc/dtmap.1 beside the dtmap binary, rendered by man) contains
every usage line, paragraph, option and section of `dtmap --help`,
`dtmap CMD --help` and `dtmap effects`; the bash completion offers exactly
each command's options and completes file values by their extension;
`dtmap --version` names dtmap, the Gmsh it runs on and the effect API;
every option of a command's table (its `--help` option list, printed from
src/cli/main.c) stands in its usage line of `dtmap CMD --help` and in the
README's usage block (issue 43: the README's `run` lacked --png and
refine's usage --optimise)."""

import os
import re
import subprocess

import gmsh

import testutil as tu

DOC = os.path.join(os.path.dirname(os.path.abspath(tu.CLI)), "doc")


def norm(text):
    return " ".join(text.split())


def cli(*args):
    code, out = tu.run(*args)
    assert code == 0, out
    return out


def commands():
    """The commands with options, from the usage lines of dtmap --help."""
    return re.findall(r"^(?:usage:)? +dtmap ([a-z]+) [A-Z]", cli("--help"), re.M)


def paragraphs(text):
    return [p for p in re.split(r"\n\s*\n", text) if p.strip()]


def help_blocks():
    """The pieces of text the manual must contain, each normalised."""
    blocks = []
    for c in commands():
        text = cli(c, "--help")
        usage, about, *rest = paragraphs(text)
        blocks.append(usage.replace("usage: ", "", 1))
        blocks.append(about)
        for p in rest:
            blocks.extend(line for line in p.splitlines()[1:])  # after "options:"
    overview = paragraphs(cli("--help"))
    summary = overview[1]
    blocks.append(summary)
    blocks.extend(line.replace("usage: ", "").strip() for line in overview[0].splitlines() if "--help" not in line
                  and "effects" not in line)
    for p in overview:
        title = p.splitlines()[0]
        if title.endswith(":") and not title.startswith("usage"):
            blocks.append(title[:-1])
            blocks.extend(p.splitlines()[1:])
    blocks.extend(cli("effects").splitlines())
    return [norm(b) for b in blocks if b.strip()]


def complete(words, cwd):
    """COMPREPLY of the generated completion for the command line words."""
    script = ("source %s; COMP_WORDS=(%s); COMP_CWORD=%d; _dtmap; printf '%%s\\n' \"${COMPREPLY[@]}\""
              % (os.path.join(DOC, "dtmap.bash-completion"), " ".join("'%s'" % w for w in words), len(words) - 1))
    out = subprocess.run(["bash", "-c", script], cwd=cwd, env=tu.plain_env(), stdout=subprocess.PIPE,
                         universal_newlines=True, check=True)
    return sorted(w for w in out.stdout.split("\n") if w)


class Docs(tu.unittest.TestCase):
    def test_man_page_has_the_help(self):
        env = tu.plain_env(MANWIDTH="4000", MANPAGER="cat", LANG="C.UTF-8")
        man = subprocess.run(["man", "-l", os.path.join(DOC, "dtmap.1")], env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, universal_newlines=True)
        self.assertEqual(man.returncode, 0, man.stderr)
        self.assertEqual(man.stderr, "")
        text = norm(man.stdout)
        blocks = help_blocks()
        self.assertGreater(len(blocks), 40)
        for b in blocks:
            self.assertTrue(b in text, "not in the man page: " + b)

    def test_completion_offers_each_commands_options(self):
        with open(os.path.join(DOC, "dtmap.bash-completion")) as f:
            script = f.read()
        names = commands()
        self.assertIn("run", names)
        self.assertGreaterEqual(len(names), 4)
        for c in names:
            options = sorted(["--help"] + re.findall(r"^  (-[-a-z]+)", cli(c, "--help"), re.M))
            found = re.search(r"^    %s\)\n(?:.*\n)*?      opts='([^']*)'" % c, script, re.M)
            self.assertIsNotNone(found, c)
            self.assertEqual(sorted(found.group(1).split()), options, c)
            self.assertEqual(complete(["dtmap", c, "-"], tu.tmpdir()), options)

    def test_completion_words(self):
        d = tu.tmpdir()
        for name in ("a.xml", "b.png", "c.csv", "d.msh"):
            open(os.path.join(d, name), "w").close()
        os.makedirs(os.path.join(d, "sub"), exist_ok=True)
        self.assertEqual(complete(["dtmap", "r"], d), ["refine", "run"])
        self.assertEqual(complete(["dtmap", "--v"], d), ["--version"])
        self.assertEqual(complete(["dtmap", "run", "--po"], d), ["--posterior"])
        self.assertEqual(complete(["dtmap", "run", ""], d), ["a.xml", "sub"])
        self.assertEqual(complete(["dtmap", "run", "a.xml", "-o", ""], d), ["d.msh", "sub"])
        self.assertEqual(complete(["dtmap", "sweep", "a.xml", "--plot", ""], d), ["b.png", "sub"])
        self.assertEqual(complete(["dtmap", "sweep", "a.xml", "--csv", ""], d), sorted(os.listdir(d)))
        self.assertEqual(complete(["dtmap", "run", "a.xml", "-j", ""], d), [])
        self.assertEqual(complete(["dtmap", "snapshot", ""], d), ["d.msh", "sub"])

    def test_usage_lines_name_every_option(self):
        with open(os.path.join(tu.SRC, "README.md")) as f:
            readme = f.read()
        block = re.search(r"^## Usage\n+```\n(.*?)```", readme, re.M | re.S).group(1)
        usage = {}  # command -> the README's usage text, continuation lines included
        for line in block.splitlines():
            m = re.match(r"^dtmap ([a-z]+) +(.*)", line)
            if m:
                current = m.group(1)
                usage[current] = m.group(2)
            elif line.startswith(" ") and current in usage:
                usage[current] += " " + line.strip()
        option = re.compile(r"(?<![\w-])(--?[a-z][-a-z]*)")
        for c in commands():
            text = cli(c, "--help")
            table = set(re.findall(r"^  (-[-a-z]+)", text, re.M))
            self.assertGreater(len(table), 1, c)
            line = paragraphs(text)[0]
            self.assertEqual(table - set(option.findall(line)), set(), "not in `dtmap %s --help`'s usage" % c)
            self.assertIn(c, usage)
            self.assertEqual(table - set(option.findall(usage[c])), set(), "not in README's usage of %s" % c)

    def test_version(self):
        lines = cli("--version").splitlines()
        self.assertEqual(len(lines), 3)
        self.assertRegex(lines[0], r"^dtmap \d+\.\d+\.\d+ \(libdtmap \d+\.\d+\.\d+\)$")
        gmsh.initialize(["t306", "-v", "0"])
        version = gmsh.option.getString("General.Version")
        gmsh.finalize()
        self.assertTrue(lines[1].startswith("Gmsh %s (built against the Gmsh API " % version), lines[1])
        self.assertTrue(lines[2].startswith("effect API %d " % tu.effect_api_version()), lines[2])
        code, out = tu.run("--version", "x")
        self.assertEqual(code, 2, out)


if __name__ == "__main__":
    tu.main()
