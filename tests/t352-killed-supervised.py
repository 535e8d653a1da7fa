"""A killed dtmap leaves no process and no file behind (src/cli/supervise.c).
The command forks one worker that does the whole job; the worker asks to die
with it (PR_SET_PDEATHSIG), the command passes SIGINT, SIGTERM and SIGHUP on
to it, and every temporary has no name that could outlive them (Gmsh's log
and scratch files are unnamed; outputs and refine's meshes are unnamed files
reached by a link, which the signal handlers remove).

- `dtmap run` on the reinforced block at 12 mm (Gmsh's Delaunay meshes it in
  about 30 s on this machine), killed while Gmsh meshes (the progress line,
  on a terminal with DTMAP_PROGRESS_AFTER=0, shows "meshing"), by SIGKILL,
  SIGTERM and SIGINT to the command's own pid: the worker is gone (exited,
  or a zombie its new parent has not reaped) within 0.5 s, $TMPDIR (the
  test's own) is empty within 3 s, and no output or temporary is beside the
  output path. After SIGTERM and SIGINT the command ends by that signal.
- `dtmap refine` on the bundled box at 4 mm, with a target 1.3 times its
  recommended step, killed by SIGKILL while a remesh meshes (in a child of the
  worker, src/gmsh/contain.c): the worker and that child are gone within
  0.5 s, $TMPDIR is empty within 3 s.
- The worker killed by SIGKILL (as the OOM killer does) while Gmsh meshes:
  the command says so, naming the stage and the signal, exits 3 and leaves
  nothing.

Each case prints how long the processes and the files took to go.
"""

import os
import pty
import select
import shutil
import signal
import subprocess
import time
import unittest

import testutil as tu

PROCESS_GONE = 0.5  # s: the bound for the worker
FILES_GONE = 3.0    # s: the bound for $TMPDIR


def scene(name, geometry, size, was):
    """The bundled scene geometry with <meshing size> was replaced by size, as name."""
    for ext in ("geo", "xml"):
        shutil.copy(os.path.join(tu.SRC, "geometries", geometry + "." + ext), tu.tmpdir())
    with open(tu.path(geometry + ".xml")) as f:
        text = f.read().replace('size="%s"' % was, 'size="%g"' % size)
    return tu.write(name, text)


def block(name):
    return scene(name, "reinforced_block", 0.012, "0.05")


def children(pid):
    """Pids whose parent is pid."""
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open("/proc/%s/stat" % d) as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        out.append(int(d))
            except (OSError, IndexError, ValueError):
                pass
    return out


def gone(pid):
    """pid has ended: no such process, or a zombie nobody reaped yet."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


def wait_until(test, limit):
    """Seconds until test() holds, polled every 5 ms; None past limit."""
    t0 = time.monotonic()
    while not test():
        if time.monotonic() - t0 > limit:
            return None
        time.sleep(0.005)
    return time.monotonic() - t0


class Killed(unittest.TestCase):
    def tearDown(self):
        """A failed case leaves no dtmap running."""
        for pid in getattr(self, "pids", []):
            if not gone(pid):
                os.kill(pid, signal.SIGKILL)

    def start(self, args, stage):
        """Start dtmap with stderr on a terminal; return it once the progress line shows stage."""
        self.tmp = tu.path("tmp-%d" % len(os.listdir(tu.tmpdir())))
        os.mkdir(self.tmp)
        master, slave = pty.openpty()
        env = dict(os.environ, TMPDIR=self.tmp, DTMAP_PROGRESS_AFTER="0")
        p = subprocess.Popen([tu.CLI] + args, cwd=tu.tmpdir(), env=env, stdout=subprocess.DEVNULL, stderr=slave)
        os.close(slave)
        self.pids = [p.pid]
        seen = b""
        while stage.encode() not in seen:
            ready, _, _ = select.select([master], [], [], 120)
            self.assertTrue(ready, "no progress line within 120 s: %r" % seen[-300:])
            try:
                seen += os.read(master, 4096)
            except OSError:
                self.fail("dtmap ended before %s: %r" % (stage, seen[-300:]))
        self.master = master
        return p

    def worker(self, p):
        """The command's one worker process."""
        workers = children(p.pid)
        self.pids += workers
        self.assertEqual(len(workers), 1, workers)
        return workers[0]

    def finish(self, p):
        os.close(self.master)
        return p.wait()

    def no_files(self):
        return not os.listdir(self.tmp)

    def no_output(self, out):
        left = [f for f in os.listdir(tu.tmpdir()) if f.startswith(out) or f.startswith("." + out)]
        self.assertEqual(left, [])

    def kill_run(self, sig):
        p = self.start(["run", block("rb12.xml"), "-o", "rb12_%d.msh" % sig], "meshing")
        worker = self.worker(p)
        os.kill(p.pid, sig)
        t_worker = wait_until(lambda: gone(worker), PROCESS_GONE)
        t_files = wait_until(self.no_files, FILES_GONE)
        code = self.finish(p)
        print("run, %s to the command while Gmsh meshes: worker gone after %s s, $TMPDIR empty after %s s" %
              (signal.Signals(sig).name, t_worker, t_files))
        self.assertIsNotNone(t_worker, "the worker outlived the command by %s s" % PROCESS_GONE)
        self.assertIsNotNone(t_files, "left in $TMPDIR: %s" % os.listdir(self.tmp))
        self.assertEqual(code, -sig)
        self.no_output("rb12_%d.msh" % sig)

    def test_sigkill(self):
        self.kill_run(signal.SIGKILL)

    def test_sigterm(self):
        self.kill_run(signal.SIGTERM)

    def test_sigint(self):
        self.kill_run(signal.SIGINT)

    def test_refine(self):
        xml = scene("box_refine.xml", "box", 4e-3, "8e-3")  # about 7e4 tets: each mesh takes seconds
        p = self.start(["refine", xml, "--target", "2.5e-7", "-o", "box_r.msh"], "round 1 > meshing")
        worker, meshing = self.worker(p), []
        wait_until(lambda: meshing.extend(children(worker)) or meshing, 5)  # forked once its files are made
        self.pids += meshing
        self.assertEqual(len(meshing), 1, "the remesh's child: %s" % meshing)
        os.kill(p.pid, signal.SIGKILL)
        t_procs = wait_until(lambda: gone(worker) and gone(meshing[0]), PROCESS_GONE)
        t_files = wait_until(self.no_files, FILES_GONE)
        self.finish(p)
        print("refine, SIGKILL to the command while a remesh meshes: worker and its child gone after %s s, "
              "$TMPDIR empty after %s s" % (t_procs, t_files))
        self.assertIsNotNone(t_procs)
        self.assertIsNotNone(t_files, "left in $TMPDIR: %s" % os.listdir(self.tmp))
        self.no_output("box_r.msh")

    def test_worker_killed(self):
        p = self.start(["run", block("rb12w.xml"), "-o", "rb12w.msh"], "meshing")
        os.kill(self.worker(p), signal.SIGKILL)
        seen = b""
        while True:
            try:
                chunk = os.read(self.master, 4096)
            except OSError:
                break
            if not chunk:
                break
            seen += chunk
        code = self.finish(p)
        self.assertEqual(code, 3, seen)
        self.assertIn(b"meshing: Gmsh crashed (signal 9, Killed)", seen)
        self.assertTrue(self.no_files(), os.listdir(self.tmp))
        self.no_output("rb12w.msh")


if __name__ == "__main__":
    tu.main()
