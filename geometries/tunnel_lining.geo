// A circular tunnel in rock with a thin concrete lining, 2D plane strain,
// SI units (m): a 20 x 20 m block of rock with a 3 m radius opening, lined
// with 0.3 m of concrete (the annulus 3 <= r <= 3.3). The example for thin
// layers: the lining's elements set the step, and no mesh of a 0.3 m layer
// lifts them past what one well-shaped element across it reaches.
//
// Physical groups: surface "rock", surface "lining".
// No "Mesh" or "Save" command; the scene's <meshing size> sets the size.

SetFactory("OpenCASCADE");

Rectangle(1) = {-10, -10, 0, 20, 20};
Disk(2) = {0, 0, 0, 3.3, 3.3}; // outer face of the lining
Disk(3) = {0, 0, 0, 3.0, 3.0}; // the opening
BooleanFragments{ Surface{1}; Delete; }{ Surface{2, 3}; Delete; }
Recursive Delete { Surface{3}; }

Physical Surface("rock") = {4};
Physical Surface("lining") = {5};
