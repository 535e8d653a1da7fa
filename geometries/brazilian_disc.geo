// Brazilian disc (indirect tensile) test, 2D, SI units (m).
// A granite disc of diameter 50 mm is loaded between two steel platens
// (60 mm x 10 mm). The disc is given small flats (contact width 2a = 4 mm)
// at top and bottom so that each platen shares a straight contact segment
// with the disc; BooleanFragments makes the mesh conforming across it.
//
// Physical groups:
//   surfaces (dim 2): "rock", "platen_top", "platen_bottom"
//   curves   (dim 1): "contact_top", "contact_bottom" (disc/platen interfaces),
//                     "load_top", "load_bottom" (outer platen faces),
//                     "rim" (free boundary of the disc)
// No "Mesh" or "Save" command: dtmap meshes through the Gmsh API and applies
// the scene's <meshing size/min-size> as Mesh.MeshSizeMax/MeshSizeMin.

SetFactory("OpenCASCADE");

R  = 0.025;            // disc radius
a  = 0.002;            // half-width of the flat contact
W  = 0.060;            // platen width
T  = 0.010;            // platen thickness
yc = Sqrt(R^2 - a^2);  // height of the flats
eps = 1e-6;            // bounding-box tolerance

// Disc with flats: the disc intersected with a slab |y| <= yc.
Disk(1) = {0, 0, 0, R};
Rectangle(2) = {-R - 1e-3, -yc, 0, 2 * R + 2e-3, 2 * yc};
BooleanIntersection(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };

// Platens.
Rectangle(4) = {-W / 2,  yc,     0, W, T};
Rectangle(5) = {-W / 2, -yc - T, 0, W, T};

// Conforming fragments: the contact segments become shared curves.
BooleanFragments{ Surface{3, 4, 5}; Delete; }{}

rock[]   = Surface In BoundingBox{-R - eps, -yc - eps, -eps, R + eps,  yc + eps,     eps};
ptop[]   = Surface In BoundingBox{-W/2 - eps, yc - eps, -eps, W/2 + eps,  yc + T + eps, eps};
pbot[]   = Surface In BoundingBox{-W/2 - eps, -yc - T - eps, -eps, W/2 + eps, -yc + eps, eps};

Physical Surface("rock")          = {rock[]};
Physical Surface("platen_top")    = {ptop[]};
Physical Surface("platen_bottom") = {pbot[]};

ctop[] = Curve In BoundingBox{-a - eps,  yc - eps, -eps, a + eps,  yc + eps, eps};
cbot[] = Curve In BoundingBox{-a - eps, -yc - eps, -eps, a + eps, -yc + eps, eps};
ltop[] = Curve In BoundingBox{-W/2 - eps,  yc + T - eps, -eps, W/2 + eps,  yc + T + eps, eps};
lbot[] = Curve In BoundingBox{-W/2 - eps, -yc - T - eps, -eps, W/2 + eps, -yc - T + eps, eps};
// Disc boundary minus the two contacts.
discb[] = Abs(Boundary{ Surface{rock[]}; });
rim[] = discb[];
rim[] -= {ctop[], cbot[]};

Physical Curve("contact_top")    = {ctop[]};
Physical Curve("contact_bottom") = {cbot[]};
Physical Curve("load_top")       = {ltop[]};
Physical Curve("load_bottom")    = {lbot[]};
Physical Curve("rim")            = {rim[]};

// Local refinement near the two contacts (on both sides of the interface):
// size 0.5 mm within 1 mm of a contact segment, then growing linearly with
// slope 0.2 (2 mm is reached about 8.5 mm away). SizeMax is deliberately far
// above any sensible element size, so that away from the contacts the
// scene's <meshing size> (Mesh.MeshSizeMax) is what limits the size and
// `dtmap sweep --sizes` really changes the mesh. Likewise the scene's
// min-size (Mesh.MeshSizeMin) clamps the fine size from below.
h_fine = 5e-4;
d_fine = 1e-3;
grade  = 0.2;
h_far  = 0.05;
Field[1] = Distance;
Field[1].CurvesList = {ctop[], cbot[]};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_fine;
Field[2].DistMin = d_fine;
Field[2].SizeMax = h_far;
Field[2].DistMax = d_fine + (h_far - h_fine) / grade;
Background Field = 2;

// Let the field and the global bounds alone decide the size.
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
