// A volume bounded by a surface read from an STL (12 triangles): the
// first mesh fills it, but a remesh clears the surface mesh, which a
// discrete surface without a parametrisation cannot get back, so Gmsh
// refuses the remesh (dtmap refine keeps round 0).
Merge "cube.stl";
Surface Loop(1) = {1};
Volume(1) = {1};
Physical Volume("block") = {1};
Mesh.MeshSizeMax = 0.2;
