// One quadrangle shell element and one beam element, apart: a 0.1 m square
// in the plane z = 0 (group "plate") and a 0.05 m line along z from
// (1, 1, 1) (group "rod"). Transfinite with two nodes per curve, so each is
// exactly one element whatever the mesh size. For the closed forms of
// tests/t333-shells-beams.py.
h = 0.1;
Point(1) = {0, 0, 0};
Point(2) = {h, 0, 0};
Point(3) = {h, h, 0};
Point(4) = {0, h, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point(5) = {1, 1, 1};
Point(6) = {1, 1, 1.05};
Line(5) = {5, 6};
Transfinite Curve{1 : 5} = 2;
Transfinite Surface{1};
Recombine Surface{1};
Physical Surface("plate") = {1};
Physical Curve("rod") = {5};
