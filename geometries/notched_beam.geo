// Notched beam for a three-point bending test, 3D, SI units (m).
// Beam 0.2 m (x, length) x 0.05 m (y, width) x 0.05 m (z, height) with a
// 2 mm wide, 15 mm deep notch at mid-span, cut from the bottom face (z = 0)
// through the whole width. Support lines (bottom, x = 0.01 and x = 0.19,
// span 0.18 m) and the load line (top, mid-span) are embedded in the faces.
// The mesh is refined around the notch tip (the two edges at z = 15 mm).
//
// Physical groups:
//   volume  (dim 3): "beam"
//   surfaces(dim 2): "notch" (the three faces of the notch)
//   curves  (dim 1): "support_left", "support_right", "load", "notch_tip"
// No "Mesh" or "Save" command: dtmap meshes through the Gmsh API and applies
// the scene's <meshing size/min-size> as Mesh.MeshSizeMax/MeshSizeMin.

SetFactory("OpenCASCADE");

Lx = 0.2;     // length
Ly = 0.05;    // width
Lz = 0.05;    // height
wn = 0.002;   // notch width
dn = 0.015;   // notch depth
xs = 0.01;    // support distance from the beam ends
eps = 1e-6;   // bounding-box tolerance

Box(1) = {0, 0, 0, Lx, Ly, Lz};
Box(2) = {Lx / 2 - wn / 2, -Ly, -Lz, wn, 3 * Ly, Lz + dn};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

// Support and load lines, embedded in the bottom and top faces.
Point(101) = {xs, 0, 0};      Point(102) = {xs, Ly, 0};
Point(103) = {Lx - xs, 0, 0}; Point(104) = {Lx - xs, Ly, 0};
Point(105) = {Lx / 2, 0, Lz}; Point(106) = {Lx / 2, Ly, Lz};
Line(101) = {101, 102};
Line(102) = {103, 104};
Line(103) = {105, 106};
BooleanFragments{ Volume{3}; Delete; }{ Curve{101, 102, 103}; Delete; }

beam[] = Volume "*";
Physical Volume("beam") = {beam[]};

notch[] = Surface In BoundingBox{Lx/2 - wn/2 - eps, -eps, -eps, Lx/2 + wn/2 + eps, Ly + eps, dn + eps};
Physical Surface("notch") = {notch[]};

tip[]  = Curve In BoundingBox{Lx/2 - wn/2 - eps, -eps, dn - eps, Lx/2 + wn/2 + eps, Ly + eps, dn + eps};
tip[] -= Curve In BoundingBox{Lx/2 - wn/2 - eps, -eps, dn - eps, Lx/2 + wn/2 + eps, eps, dn + eps};
tip[] -= Curve In BoundingBox{Lx/2 - wn/2 - eps, Ly - eps, dn - eps, Lx/2 + wn/2 + eps, Ly + eps, dn + eps};
Physical Curve("notch_tip")     = {tip[]};
Physical Curve("support_left")  = Curve In BoundingBox{xs - eps, -eps, -eps, xs + eps, Ly + eps, eps};
Physical Curve("support_right") = Curve In BoundingBox{Lx - xs - eps, -eps, -eps, Lx - xs + eps, Ly + eps, eps};
Physical Curve("load")          = Curve In BoundingBox{Lx/2 - eps, -eps, Lz - eps, Lx/2 + eps, Ly + eps, Lz + eps};

// Refinement at the notch tip: 1.5 mm within 3 mm of the tip edges, then
// growing linearly with slope 0.12 (8 mm is reached about 57 mm away).
// SizeMax is deliberately far above any sensible element size, so the
// scene's <meshing size> (Mesh.MeshSizeMax, 8 mm in notched_beam.xml) sets
// the coarse size and `dtmap sweep --sizes` really changes the mesh.
h_fine = 1.5e-3;
d_fine = 3e-3;
grade  = 0.12;
h_far  = 0.05;
Field[1] = Distance;
Field[1].CurvesList = {tip[]};
Field[1].NumPointsPerCurve = 100;
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
