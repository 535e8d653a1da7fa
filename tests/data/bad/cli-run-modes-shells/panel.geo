// Stiffened cylindrical panel, SI units (m): a 60-degree arc of a cylinder
// of radius 1 m and length 1.2 m, 5 mm steel skin, with one rectangular
// steel stiffener along its crown. The example for shell and beam sections.
//
// - skin: two surfaces, one each side of the crown, made by extruding the
//   two arcs along y; meshed as triangles (or quadrangles with
//   Mesh.RecombineAll = 1).
// - stiffener: the straight line at the crown (x = 0, z = R) that the two
//   surfaces share, meshed as line elements on the skin's nodes.
//
// Physical groups:
//   surfaces (dim 2): "skin"
//   curve    (dim 1): "stiffener"
// No "Mesh" command; the scene's <meshing size=...> sets the size.

R = 1.0;       // radius
L = 1.2;       // length along y
a = Pi / 6;    // half opening angle

Point(1) = {0, 0, 0};
Point(2) = {-R * Sin(a), 0, R * Cos(a)};
Point(3) = {0, 0, R};
Point(4) = {R * Sin(a), 0, R * Cos(a)};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
left[] = Extrude {0, L, 0} { Curve{1}; };
right[] = Extrude {0, L, 0} { Curve{2}; };

Physical Surface("skin") = {left[1], right[1]};
// The extrusion's lateral curve through point 3 (the crown), shared by both.
Physical Curve("stiffener") = {left[2]};
