# Mesh a steel box with Gmsh's Python API and print dtmap's recommended step.
import gmsh, dtmap
gmsh.initialize(["box.py", "-v", "2"])  # Gmsh says only warnings and errors
gmsh.model.occ.addBox(0, 0, 0, 0.1, 0.1, 0.1)
gmsh.model.occ.synchronize()
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.02)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.Binary", 1)  # every digit, so `dtmap run` reads the same mesh
gmsh.write("box.msh")
r = dtmap.analyse(materials={"steel": dict(default=True, E=210e9, nu=0.3, rho=7850)}, effects=["elastic"])
print("recommended step %.17g s (%s)" % (r.recommended, r.basis))
