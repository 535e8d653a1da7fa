// A slab extruded from a free square in 4 layers: the curves along the
// extrusion keep 5 nodes whatever the size field says.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
out[] = Extrude{0, 0, 0.2}{ Surface{1}; Layers{4}; };
Physical Volume("block") = {out[1]};
Mesh.MeshSizeMax = 0.1;
