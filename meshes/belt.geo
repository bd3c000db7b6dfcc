// A belt (or plate) section as a user would write it in gmsh: a rectangular slab,
// clamped at its two ends, that particles fall on. Shipped with gsi as the example of a
// structure loaded from the user's own .geo file (case key structures.file).
//
// Geometry (m): the slab spans x in [-length/2, length/2], y in [-width/2, width/2],
// z in [0, thickness]; its in-plane mesh of size h is extruded through the thickness in
// `layers` element layers (each prism split into tetrahedra), so that bending is resolved
// through the thickness even when h >> thickness (use degree = 2 in gsi for bending).
//
// Every DefineConstant can be overridden from the case file, by its last name, e.g.
//   geometry = { length = 1.2, h = 0.04 }
// Physical groups (named the user's way; map them to gsi's names with structures.tags):
//   "belt_top" (z = thickness, the face the particles touch), "belt_bottom" (z = 0),
//   "belt_ends" (x = -length/2 and x = length/2), "belt_sides" (y = +-width/2),
//   "belt_volume".
SetFactory("OpenCASCADE");

DefineConstant[
  length = {0.8, Name "Parameters/length"},
  width = {0.3, Name "Parameters/width"},
  thickness = {0.01, Name "Parameters/thickness"},
  h = {0.05, Name "Parameters/h"},
  layers = {1, Name "Parameters/layers"}
];

Rectangle(1) = {-length / 2, -width / 2, 0, length, width};
MeshSize{ PointsOf{ Surface{1}; } } = h;
out[] = Extrude {0, 0, thickness} { Surface{1}; Layers{layers}; };

eps = 1e-3 * thickness;
top[] = Surface In BoundingBox{-length, -width, thickness - eps, length, width, thickness + eps};
bottom[] = Surface In BoundingBox{-length, -width, -eps, length, width, eps};
ends[] = Surface In BoundingBox{-length / 2 - eps, -width, -eps, -length / 2 + eps, width, thickness + eps};
ends[] += Surface In BoundingBox{length / 2 - eps, -width, -eps, length / 2 + eps, width, thickness + eps};
sides[] = Surface In BoundingBox{-length, -width / 2 - eps, -eps, length, -width / 2 + eps, thickness + eps};
sides[] += Surface In BoundingBox{-length, width / 2 - eps, -eps, length, width / 2 + eps, thickness + eps};

Physical Surface("belt_top") = {top[]};
Physical Surface("belt_bottom") = {bottom[]};
Physical Surface("belt_ends") = {ends[]};
Physical Surface("belt_sides") = {sides[]};
Physical Volume("belt_volume") = {out[1]};
