// Three transfinite quadrangles in a row that share their vertical curves,
// so every vertical curve must keep one count. The first has a graded
// (progression) bottom and top; the third's top side is two curves, whose
// counts must add up to its bottom's. The graded bottom and the third
// quadrangle hold the smallest elements. refine sets all of them from its size
// suggestion, consistently, or a transfinite surface refuses to mesh.
Point(1) = {0, 0, 0};   Point(2) = {1, 0, 0};   Point(3) = {2, 0, 0};   Point(4) = {3, 0, 0};
Point(5) = {0, 1, 0};   Point(6) = {1, 1, 0};   Point(7) = {2, 1, 0};   Point(8) = {3, 1, 0};
Point(9) = {2.4, 1, 0};
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};              // bottom
Line(4) = {5, 6};  Line(5) = {6, 7};  Line(6) = {7, 9}; Line(7) = {9, 8}; // top (the third is 6 + 7)
Line(8) = {1, 5};  Line(9) = {2, 6};  Line(10) = {3, 7}; Line(11) = {4, 8}; // verticals
Curve Loop(1) = {1, 9, -4, -8};       Plane Surface(1) = {1};
Curve Loop(2) = {2, 10, -5, -9};      Plane Surface(2) = {2};
Curve Loop(3) = {3, 11, -7, -6, -10}; Plane Surface(3) = {3};
Transfinite Curve{1, 4} = 31 Using Progression 1.03;
Transfinite Curve{2, 5} = 21;
Transfinite Curve{3} = 41;
Transfinite Curve{6} = 17;
Transfinite Curve{7} = 25;
Transfinite Curve{8:11} = 21;
Transfinite Surface{1};
Transfinite Surface{2};
Transfinite Surface{3} = {3, 4, 8, 7};
Physical Surface("block") = {1, 2, 3};
