"""Screenshot of Gmsh's GUI with dtmap as its ONELAB solver (used by
scripts/screenshots.sh under a virtual display). Opens the geometry in
Gmsh's window with dtmap registered as solver 0, runs dtmap's "check" and
"compute" actions through Gmsh's own ONELAB server (what the Run button
does), opens dtmap's panel and grabs the whole screen.

usage: gui_screenshot.py MODEL.geo DTMAP OUT.png"""
import sys

import gmsh
from PIL import ImageGrab

model, exe, out = sys.argv[1:4]
gmsh.initialize()
gmsh.option.setNumber("General.GraphicsWidth", 1280)
gmsh.option.setNumber("General.GraphicsHeight", 800)
gmsh.option.setNumber("General.MenuWidth", 330)
gmsh.option.setString("Solver.Name0", "dtmap")
gmsh.option.setString("Solver.Executable0", exe)
gmsh.open(model)
gmsh.fltk.initialize()
gmsh.option.setNumber("General.Trackball", 0)
gmsh.option.setNumber("General.RotationX", -60)
gmsh.option.setNumber("General.RotationZ", -25)
for action in ("check", "compute"):
    gmsh.onelab.setString("dtmap/Action", [action])
    gmsh.onelab.run("dtmap", exe)
gmsh.fltk.update()
gmsh.fltk.openTreeItem("0Modules/Solver/dtmap")
for _ in range(30):
    gmsh.fltk.wait(0.1)
gmsh.graphics.draw()
image = ImageGrab.grab()
box = image.convert("L").point(lambda v: 255 if v > 0 else 0).getbbox()
image.crop(box).save(out)
gmsh.finalize()
