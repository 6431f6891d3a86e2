# Yade script: yade -n -j1 -x yade_check_damped_law.py
# Checks, on one pair of unequal overlapping spheres in Yade 2023.02a, the
# conventions reference_damped.py assumes (CONVENTIONS_DAMPING.md):
#  ViscElPhys: force on body 2 = (kn delta + cn n.u) n + (ks h + cs) P u in the
#    step after the shear force is reset, u = (v1 + w1 x c1) - (v2 + w2 x c2) the
#    relative velocity at the contact point with the state (half-step) velocities,
#    c_i = contactPoint - x_i; torques c2 x f on 2, -c1 x f on 1.
#  CohFrictPhys (always_use_moment_law): after body 1 is turned by a small
#    rotation theta1 (no velocities), the torque on body 1 is
#    -(kr P + ktw n n^T) theta1 and on body 2 the opposite.
# Prints measured/expected ratios (all 1 to ~1e-6); output in data/check_damped_law.txt.
import math

r1, r2 = 0.004, 0.006
delta = 1.0e-5
l = r1 + r2 - delta
n = Vector3(1, 2, 2) / 3.0
p1 = Vector3(0.1, 0.1, 0.1)
lines = []

def emit(s):
    print(s)
    lines.append(s)

def ratio(a, b):
    return (a.dot(b)) / b.squaredNorm() if b.squaredNorm() > 0 else float('nan')

# ---------------------------------------------------------------- ViscElPhys
O.reset()
mat = O.materials.append(ViscElMat(tc=2e-4, en=0.5, et=0.5, density=2500, frictionAngle=math.atan(1e6)))
b1 = O.bodies.append(sphere(p1, r1, material=mat))
b2 = O.bodies.append(sphere(p1 + l * n, r2, material=mat))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                             [Law2_ScGeom_ViscElPhys_Basic()]),
             NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
O.dt = 1e-8
O.step()
i = O.interactions[b1, b2]
kn, ks, cn, cs = i.phys.kn, i.phys.ks, i.phys.cn, i.phys.cs
s1, s2 = O.bodies[b1].state, O.bodies[b2].state
v1, v2 = Vector3(0.01, -0.02, 0.005), Vector3(-0.004, 0.003, 0.02)
w1, w2 = Vector3(3.0, -1.0, 2.0), Vector3(-2.0, 4.0, 1.0)
# put the bodies back at the original overlap, set velocities, reset the shear force
s1.pos, s2.pos = p1, p1 + l * n
s1.vel, s2.vel, s1.angVel, s2.angVel = v1, v2, w1, w2
i.phys.shearForce = Vector3(0, 0, 0)
O.step()
cp = p1 + (r1 - 0.5 * delta) * n
c1, c2 = cp - p1, cp - (p1 + l * n)
u = (v1 + w1.cross(c1)) - (v2 + w2.cross(c2))
un = n.dot(u)
ut = u - un * n
f_exp = (kn * delta + cn * un) * n + (ks * O.dt + cs) * ut
f2 = O.forces.f(b2)
emit('ViscElPhys kn %.6g ks %.6g cn %.6g cs %.6g' % (kn, ks, cn, cs))
emit('  force on 2 / expected (normal part)     %.9f' % ratio(f2.dot(n) * n, f_exp.dot(n) * n))
emit('  force on 2 / expected (tangential part) %.9f' % ratio(f2 - f2.dot(n) * n, f_exp - f_exp.dot(n) * n))
emit('  force on 1 / -(force on 2)              %.9f' % ratio(O.forces.f(b1), -f2))
emit('  torque on 2 / (c2 x f)                  %.9f' % ratio(O.forces.t(b2), c2.cross(f_exp)))
emit('  torque on 1 / -(c1 x f)                 %.9f' % ratio(O.forces.t(b1), -c1.cross(f_exp)))

# ---------------------------------------------------------------- CohFrictPhys
O.reset()
mat = O.materials.append(CohFrictMat(young=2e7, poisson=0.3, density=2500, frictionAngle=math.atan(1e6),
                                     isCohesive=False, momentRotationLaw=True, alphaKr=2.0, alphaKtw=1.0))
b1 = O.bodies.append(sphere(p1, r1, material=mat))
b2 = O.bodies.append(sphere(p1 + l * n, r2, material=mat))
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D()], [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()],
                             [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True)]),
             NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
O.dt = 1e-8
O.step()
i = O.interactions[b1, b2]
kn, ks, kr, ktw = i.phys.kn, i.phys.ks, i.phys.kr, i.phys.ktw
emit('CohFrictPhys kn %.6g ks %.6g kr %.6g ktw %.6g (expected kr %.6g ktw %.6g)'
     % (kn, ks, kr, ktw, r1 * r2 * ks * 2.0, r1 * r2 * ks * 1.0))
s1, s2 = O.bodies[b1].state, O.bodies[b2].state
theta = Vector3(2e-4, -1e-4, 3e-4)
s1.pos, s2.pos = p1, p1 + l * n
s1.vel = s2.vel = s1.angVel = s2.angVel = Vector3(0, 0, 0)
s1.ori = Quaternion(theta / theta.norm(), theta.norm()) * s1.ori
i.phys.shearForce = Vector3(0, 0, 0)
O.step()
m_exp = kr * (theta - theta.dot(n) * n) + ktw * theta.dot(n) * n
t1, t2 = O.forces.t(b1), O.forces.t(b2)
emit('  torque on 1 / -(kr P + ktw n n^T) theta1   %.9f' % ratio(t1, -m_exp))
emit('  torque on 2 / +(kr P + ktw n n^T) theta1   %.9f' % ratio(t2, m_exp))
emit('  bending part / expected  %.9f   twist part / expected  %.9f'
     % (ratio(t1 - t1.dot(n) * n, -(m_exp - m_exp.dot(n) * n)), t1.dot(n) / (-m_exp.dot(n))))

import os, sys
out = os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), 'data', 'check_damped_law.txt')
with open(out, 'w') as f:
    f.write('# output of yade_check_damped_law.py (Yade 2023.02a)\n' + '\n'.join(lines) + '\n')
