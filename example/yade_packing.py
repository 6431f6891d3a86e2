# Yade script that made demstep's example/yade_packing.txt: 100 spheres of
# two materials settle under gravity in a box; the packing is exported with
# the material id of each sphere. Run: yade -n -x yade_packing.py
from yade import pack, export, utils
glass = O.materials.append(FrictMat(young=1.0e7, poisson=0.25, density=2500, frictionAngle=0.5, label='glass'))
steel = O.materials.append(FrictMat(young=2.0e7, poisson=0.3, density=7800, frictionAngle=0.5, label='steel'))
O.bodies.append(utils.aabbWalls([(0, 0, 0), (0.01, 0.01, 0.03)], thickness=0.001, material=glass))
sp = pack.SpherePack()
sp.makeCloud((0, 0, 0), (0.01, 0.01, 0.03), rMean=0.0009, rRelFuzz=0.2, num=100, seed=7)
for k, (c, r) in enumerate(sp):
    O.bodies.append(utils.sphere(c, r, material=(steel if k % 4 == 0 else glass)))
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.4)]
O.dt = 0.3*utils.PWaveTimeStep()
O.run(40000, True)
export.textExt('yade_packing.txt', format='x_y_z_r_matId')
