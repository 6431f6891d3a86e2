# Run by test_yade.py inside Yade: yade -n -j1 -x yade_sc_check.py OUT.json
# Builds the periodic "sc" assembly of validation/yade as yade_stability.py does
# (216 spheres of R0 = 0.01 m, spacing 2 R0 (1 - 1e-3), FrictMat young = 1e7,
# ks/kn 0.3, density 2623), steps twice so that Yade makes its interactions, and
# asks demstep.yade for the limit of O; writes what it read and the result.
import json
import math
import sys

import demstep.yade

R0, OVERLAP, N = 0.01, 1.0e-3, 6
mat = O.materials.append(FrictMat(young=1.0e5 / R0, poisson=0.3, density=2623.0,
                                  frictionAngle=math.atan(1.0e6)))
a = 2 * R0 * (1 - OVERLAP)
O.periodic = True
O.cell.hSize = Matrix3(N * a, 0, 0, 0, N * a, 0, 0, 0, N * a)
for i in range(N):
    for j in range(N):
        for k in range(N):
            O.bodies.append(sphere(Vector3((i + 0.25) * a, (j + 0.25) * a, (k + 0.25) * a), R0, material=mat))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=0.05 * R0),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(damping=0.0, gravity=(0, 0, 0))]
O.dt = 1e-6
O.step()
O.step()
result = demstep.yade.critical_steps(O)
real = [i for i in O.interactions if i.isReal]
with open(sys.argv[-1], "w") as out:
    json.dump({"yade_version": version, "n_bodies": len(O.bodies), "n_interactions": len(real),
               "kn": sorted({i.phys.kn for i in real}), "ks": sorted({i.phys.ks for i in real}),
               "result": {name: getattr(result, name) for name in ("dt_critical_eigen", "n_dof", "n_springs",
                                                                   "periodic", "rotation")}}, out)
sys.exit(0)
