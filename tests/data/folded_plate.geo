// A folded plate for the distributed membrane test (t914): a 0.3 x 2 m
// strip in z = 0 and another standing up from its edge y = 0 (in the plane
// y = 0), one surface model in 3D; physical surface "skin". The legs are
// long away from the fold, so a partition leaves the tip of a leg, flat, in
// a part of its own.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 0.3, 2};
Rectangle(2) = {0, 0, 0, 0.3, 2};
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 2} { Surface{2}; }
BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }
Physical Surface("skin") = Surface{:};
