// A square whose geometry file clamps every size to one value, as some of
// Gmsh's demos do: refine lifts the clamp for its remeshes and says so.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Physical Surface("block") = {1};
Mesh.MeshSizeMin = 0.05;
Mesh.MeshSizeMax = 0.05;
