// Two squares meshed, then partitioned into 3 by Metis (as Gmsh's tutorial
// t21 does): the mesh lives in partition entities. The curve group's name
// holds a '_', which Gmsh's unpartition takes for a partitioner's group.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Rectangle(2) = {1, 0, 0, 1, 1};
BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }
MeshSize {:} = 0.05;
Physical Surface("block", 1) = {1, 2};
Physical Curve("left_side", 2) = Curve In BoundingBox{-0.1, -0.1, -0.1, 0.1, 1.1, 0.1};
Mesh 2;
PartitionMesh 3;
