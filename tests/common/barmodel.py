"""The structured hexahedral steel bar of two cell sizes that the LS-DYNA
deck tests share (t377, t922): 0.12 x 0.04 x 0.04 m, 16 cells of
0.01 x 0.02 x 0.02 m (dt_e = 0.01 m / c_d by LS-DYNA's rule) then 16 cubes
of 0.02 m (0.02 m / c_d), one physical volume "bar"; a target between the
two steps scales only the small cells."""

import math

BAR = """Point(1) = {0, 0, 0};
l[] = Extrude {0.12, 0, 0} { Point{1}; Layers{ {4, 4}, {0.3333333333333333, 1} }; };
s[] = Extrude {0, 0.04, 0} { Line{l[1]}; Layers{2}; Recombine; };
v[] = Extrude {0, 0, 0.04} { Surface{s[1]}; Layers{2}; Recombine; };
Physical Volume("bar") = {v[1]};
"""
SCENE = """<?xml version="1.0"?>
<dtmap-scene version="1">
  <geometry file="bar.geo"/>
  <meshing dim="3"/>
  <material name="steel" groups="bar" E="%r" nu="%r" rho="%r"/>
  <effects><elastic formulation="3d"/></effects>
  <time duration="1e-4"/>
</dtmap-scene>
"""
E, NU, RHO = 210e9, 0.3, 7850.0
C_D = math.sqrt(E * (1 - NU) / (RHO * (1 + NU) * (1 - 2 * NU)))  # the dilatational wave speed, m/s
