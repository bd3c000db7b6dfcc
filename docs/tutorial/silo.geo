// A cylindrical steel silo wall as a user writes it in gmsh: open at the top and at the
// bottom (a DEM hopper cone and a slide gate close it below; see silo.toml). The wall is a
// tube of inner radius `radius`, wall thickness `thickness`, height `height`, standing on
// z = 0. Every DefineConstant can be overridden from the case file by its last name:
//   geometry = { height = 0.2, h = 0.008 }
// Physical groups (the user's own names; silo.toml maps them onto gsi's with `tags`):
//   "silo_inner"  the inner face, which the particles touch
//   "silo_outer"  the outer face
//   "silo_foot"   the bottom ring (z = 0), where the silo stands
//   "silo_rim"    the top ring (z = height)
//   "silo_wall"   the volume
SetFactory("OpenCASCADE");

DefineConstant[
  radius = {0.04, Name "Parameters/radius"},
  height = {0.16, Name "Parameters/height"},
  thickness = {0.003, Name "Parameters/thickness"},
  h = {0.006, Name "Parameters/h"}
];

Cylinder(1) = {0, 0, 0, 0, 0, height, radius + thickness};
Cylinder(2) = {0, 0, 0, 0, 0, height, radius};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
MeshSize{ PointsOf{ Volume{3}; } } = h;

e = 1e-3 * thickness;
R = radius + thickness;
inner[] = Surface In BoundingBox{-radius - e, -radius - e, -e, radius + e, radius + e, height + e};
foot[] = Surface In BoundingBox{-R - e, -R - e, -e, R + e, R + e, e};
rim[] = Surface In BoundingBox{-R - e, -R - e, height - e, R + e, R + e, height + e};
outer[] = Surface In BoundingBox{-R - e, -R - e, -e, R + e, R + e, height + e};
outer[] -= {inner[], foot[], rim[]};

Physical Surface("silo_inner") = {inner[]};
Physical Surface("silo_outer") = {outer[]};
Physical Surface("silo_foot") = {foot[]};
Physical Surface("silo_rim") = {rim[]};
Physical Volume("silo_wall") = {3};
