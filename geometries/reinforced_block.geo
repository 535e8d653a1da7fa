// Reinforced concrete block, 3D, SI units (m): a 0.4 x 0.4 x 1.0 m concrete
// block with four straight longitudinal steel rebars and one thin steel plate
// embedded in it. The example for mixed solid / truss / membrane "sections".
//
// - rebars: four lines along z, at 0.05 m cover from the side faces
//   (x, y in {0.05, 0.35}), from z = 0.05 to z = 0.95; meshed as line
//   elements that share their nodes with the tetrahedra (embedded).
// - plate:  a 0.2 x 0.2 m square at z = 0.5, x and y from 0.1 to 0.3;
//   meshed as triangles that share their nodes with the tetrahedra.
//   It does not touch the rebars.
//
// Physical groups:
//   volume  (dim 3): "concrete"
//   curves  (dim 1): "rebar"
//   surface (dim 2): "plate"
// No "Mesh" or "Save" command; the scene's <meshing size="0.05"> sets the
// size (about 6.8k tetrahedra).

SetFactory("OpenCASCADE");

W = 0.4;       // width in x and y
H = 1.0;       // length along z
c = 0.05;      // rebar cover (from the side faces and from the ends)
zp = 0.5;      // height of the plate
a = 0.1;       // plate spans [a, W - a] in x and y

Box(1) = {0, 0, 0, W, W, H};

// Rebars: one straight line each.
xs[] = {c, W - c, W - c, c};
ys[] = {c, c, W - c, W - c};
bars[] = {};
For i In {0 : 3}
  p0 = newp; Point(p0) = {xs[i], ys[i], c};
  p1 = newp; Point(p1) = {xs[i], ys[i], H - c};
  l = newl;  Line(l) = {p0, p1};
  bars[] += {l};
EndFor

// Plate: a rectangle in the plane z = zp.
plate = news;
Rectangle(plate) = {a, a, zp, W - 2 * a, W - 2 * a};

Curve{bars[]} In Volume{1};
Surface{plate} In Volume{1};

Physical Volume("concrete") = {1};
Physical Curve("rebar") = {bars[]};
Physical Surface("plate") = {plate};
