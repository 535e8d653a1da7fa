// Plate with a central circular hole, 2D (plane stress), SI units (m).
// Plate 0.2 m (x) x 0.1 m (y) centred at the origin, hole radius 0.02 m.
// The mesh is refined around the hole, where the stress concentrates.
//
// Physical groups:
//   surface (dim 2): "plate"
//   curves  (dim 1): "hole", "left" (x = -0.1), "right" (x = 0.1),
//                    "bottom" (y = -0.05), "top" (y = 0.05)
// No "Mesh" or "Save" command: dtmap meshes through the Gmsh API and applies
// the scene's <meshing size/min-size> as Mesh.MeshSizeMax/MeshSizeMin.

SetFactory("OpenCASCADE");

Lx = 0.2;
Ly = 0.1;
r  = 0.02;
eps = 1e-6;

Rectangle(1) = {-Lx / 2, -Ly / 2, 0, Lx, Ly};
Disk(2) = {0, 0, 0, r};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };

Physical Surface("plate") = {3};

hole[] = Curve In BoundingBox{-r - eps, -r - eps, -eps, r + eps, r + eps, eps};
Physical Curve("hole")   = {hole[]};
Physical Curve("left")   = Curve In BoundingBox{-Lx/2 - eps, -Ly/2 - eps, -eps, -Lx/2 + eps, Ly/2 + eps, eps};
Physical Curve("right")  = Curve In BoundingBox{ Lx/2 - eps, -Ly/2 - eps, -eps,  Lx/2 + eps, Ly/2 + eps, eps};
Physical Curve("bottom") = Curve In BoundingBox{-Lx/2 - eps, -Ly/2 - eps, -eps,  Lx/2 + eps, -Ly/2 + eps, eps};
Physical Curve("top")    = Curve In BoundingBox{-Lx/2 - eps,  Ly/2 - eps, -eps,  Lx/2 + eps,  Ly/2 + eps, eps};

// Refinement around the hole: 1 mm within 2 mm of the hole, then growing
// linearly with slope 0.2 (5 mm is reached about 22 mm from the hole).
// SizeMax is deliberately far above any sensible element size, so that away
// from the hole the scene's <meshing size> (Mesh.MeshSizeMax) limits the
// size and `dtmap sweep --sizes` really changes the mesh.
h_fine = 1e-3;
d_fine = 2e-3;
grade  = 0.2;
h_far  = 0.1;
Field[1] = Distance;
Field[1].CurvesList = {hole[]};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_fine;
Field[2].DistMin = d_fine;
Field[2].SizeMax = h_far;
Field[2].DistMax = d_fine + (h_far - h_fine) / grade;
Background Field = 2;

Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
