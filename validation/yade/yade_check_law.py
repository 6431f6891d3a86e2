# Yade script: yade -n -j1 -x yade_check_law.py
# Checks, on one pair of unequal overlapping spheres in a periodic cell, the
# kinematics and lever arms that reference_6dof.py assumes for
# Ig2_Sphere_Sphere_ScGeom + Law2_ScGeom_FrictPhys_CundallStrack (Yade 2023.02a):
#   shear increment = dt P [alpha (v2 - v1) + r2 n x w2 + r1 n x w1],
#       alpha = (r1 + r2) / l   (avoidGranularRatcheting = True, the default)
#   force on 1 = -(F_n + F_s), torque on b = (r_b - delta/2) n x (force on 1).
# Prints measured/expected ratios (all should be 1 to ~1e-6).
import math
r1, r2 = 0.01, 0.015
delta = 2.0e-4
l = r1 + r2 - delta
O.periodic = True
O.cell.hSize = Matrix3(0.2, 0, 0, 0, 0.2, 0, 0, 0, 0.2)
mat = O.materials.append(FrictMat(young=1e7, poisson=0.3, density=2600, frictionAngle=math.atan(1e6)))
n = Vector3(1, 2, 2) / 3.0
p1 = Vector3(0.1, 0.1, 0.1)
b1 = O.bodies.append(sphere(p1, r1, material=mat))
b2 = O.bodies.append(sphere(p1 + l * n, r2, material=mat))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                             [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
O.dt = 1e-7
O.step()
i = O.interactions[b1, b2]
kn, ks = i.phys.kn, i.phys.ks
print('kn %.8g (expected %.8g)  ks/kn %.8g' % (kn, 2 * 1e7 * r1 * 1e7 * r2 / (1e7 * r1 + 1e7 * r2), ks / kn))
t = Vector3(2, -1, 0) / math.sqrt(5.0)      # unit tangent (t . n = 0)
alpha = (r1 + r2) / l

def run(v2, w1, w2):
    O.bodies[b1].state.vel = Vector3(0, 0, 0)
    O.bodies[b2].state.vel = v2
    O.bodies[b1].state.angVel = w1
    O.bodies[b2].state.angVel = w2
    i.phys.shearForce = Vector3(0, 0, 0)
    O.step()
    fs = i.phys.shearForce
    f1 = O.forces.f(b1)
    return fs, f1, O.forces.t(b1), O.forces.t(b2)

eps = 1e-9
# 1) tangential translation of sphere 2
fs, f1, t1, t2 = run(eps * t, Vector3(0, 0, 0), Vector3(0, 0, 0))
exp_fs = -ks * alpha * eps * O.dt * t
print('translation: shear force / (-ks alpha v dt) = %.9f  (1/alpha = %.9f: the ratio without alpha)'
      % (fs.dot(t) / exp_fs.dot(t), 1.0 / alpha))
nrm = i.geom.normal
d = i.geom.penetrationDepth
exp_t1 = (r1 - 0.5 * d) * nrm.cross(f1)
exp_t2 = (r2 - 0.5 * d) * nrm.cross(f1)
print('torque arms: t1.e/|e|^2 = %.9f (|t1 - e|/|e| = %.1e), t2.e/|e|^2 = %.9f (|t2 - e|/|e| = %.1e)'
      % (t1.dot(exp_t1) / exp_t1.squaredNorm(), (t1 - exp_t1).norm() / exp_t1.norm(),
         t2.dot(exp_t2) / exp_t2.squaredNorm(), (t2 - exp_t2).norm() / exp_t2.norm()))
# 2) rotation of sphere 1 about an axis normal to n: slip velocity r1 n x w1
w = n.cross(t)
fs, f1, t1, t2 = run(Vector3(0, 0, 0), eps / r1 * w, Vector3(0, 0, 0))
slip = r1 * n.cross(eps / r1 * w)
print('rotation 1: shear force / (-ks r1 (n x w1) dt) = %.9f' % (fs.dot(slip) / (-ks * O.dt * slip.dot(slip))))
fs, f1, t1, t2 = run(Vector3(0, 0, 0), Vector3(0, 0, 0), eps / r2 * w)
slip = r2 * n.cross(eps / r2 * w)
print('rotation 2: shear force / (-ks r2 (n x w2) dt) = %.9f' % (fs.dot(slip) / (-ks * O.dt * slip.dot(slip))))
