// A plate for the distributed shape advice (t915): a 2 x 1 block with a
// narrow V notch from its top edge (its tip at (1, 0.4), about 9.5 deg: a
// small angle) and, beside it, two sliver surfaces along its short sides,
// (0,0), (-0.02,0.5), (0,1) and (2,0), (2.02,0.5), (2,1), with one segment
// on each of their outer sides. Meshed at 0.05 m (about 2000 triangles)
// and split into three parts, the slivers' elements and their neighbours
// lie in more than one part.
Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0}; Point(4) = {0, 1, 0};
Point(6) = {1.05, 1, 0}; Point(7) = {1, 0.4, 0}; Point(8) = {0.95, 1, 0};
Point(11) = {-0.02, 0.5, 0}; Point(12) = {2.02, 0.5, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 6}; Line(4) = {6, 7}; Line(5) = {7, 8}; Line(6) = {8, 4};
Line(7) = {4, 1};
Line(8) = {1, 11}; Line(9) = {11, 4}; Line(10) = {2, 12}; Line(11) = {12, 3};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7}; Plane Surface(1) = {1};
Curve Loop(2) = {8, 9, 7}; Plane Surface(2) = {2};
Curve Loop(3) = {10, 11, -2}; Plane Surface(3) = {3};
Transfinite Curve{8, 9, 10, 11} = 2;
Physical Surface("block") = {1};
Physical Surface("sliver") = {2, 3};
