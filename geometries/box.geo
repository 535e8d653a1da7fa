// Steel block, 3D, SI units (m): a 0.1 m cube meshed with a uniform size.
// The simplest 3D example; useful for checks against analytic wave speeds.
//
// Physical groups:
//   volume  (dim 3): "block"
//   surfaces(dim 2): "bottom" (z = 0), "top" (z = 0.1)
// No "Mesh" or "Save" command and no size setting: dtmap meshes through the
// Gmsh API and applies the scene's <meshing size/min-size> as
// Mesh.MeshSizeMax/MeshSizeMin.

SetFactory("OpenCASCADE");

L = 0.1;
eps = 1e-6;

Box(1) = {0, 0, 0, L, L, L};

Physical Volume("block") = {1};
Physical Surface("bottom") = Surface In BoundingBox{-eps, -eps, -eps, L + eps, L + eps, eps};
Physical Surface("top")    = Surface In BoundingBox{-eps, -eps, L - eps, L + eps, L + eps, L + eps};
