# Yade script: yade -n -j1 -x yade_check_damped_single.py
# The exact damped limit on the smallest damped system: one ViscElPhys sphere
# resting under gravity on a fixed facet (normal spring and dashpot; tangential
# spring and dashpot coupling the sliding translation with the rotation through
# the lever arm). Yade's largest stable step is bisected on kinetic-energy growth
# from the rested state (same materials as the viscel scene, no local damping),
# and compared with reference_damped.py's assembly of the same contact.
# Output: data/check_damped_single.txt
import math, os, sys, random
HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import reference_damped as ref          # plain numpy/scipy

R, DENSITY, TC, EN, ET = 0.005, 2500.0, 2.0e-4, 0.5, 0.5
mat = O.materials.append(ViscElMat(tc=TC, en=EN, et=ET, density=DENSITY, frictionAngle=0.5))
floor = O.bodies.append(facet([Vector3(-0.05, -0.05, 0), Vector3(0.05, -0.05, 0), Vector3(0, 0.08, 0)],
                              material=mat, fixed=True))
ball = O.bodies.append(sphere(Vector3(0.001, 0.002, R * 0.999), R, material=mat))
O.engines = [ForceResetter(),
             InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()]),
             InteractionLoop([Ig2_Facet_Sphere_ScGeom()], [Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                             [Law2_ScGeom_ViscElPhys_Basic()]),
             NewtonIntegrator(damping=0.3, gravity=(0, 0, -9.81), label='newton')]
O.dt = 1e-6
for q in range(20):
    O.run(2000, True)
    O.bodies[ball].state.vel = Vector3(0, 0, 0)
    O.bodies[ball].state.angVel = Vector3(0, 0, 0)
newton.damping = 0.0
O.saveTmp('rest')
I = O.interactions[floor, ball]
s = O.bodies[ball].state
g = I.geom
row = {'kind1': 'w', 'i1': '0', 'kind2': 'p', 'i2': '0',
       'nx': g.normal[0], 'ny': g.normal[1], 'nz': g.normal[2],
       'cpx': g.contactPoint[0], 'cpy': g.contactPoint[1], 'cpz': g.contactPoint[2],
       'overlap': g.penetrationDepth, 'refR1': g.refR1, 'refR2': g.refR2,
       'kn': I.phys.kn, 'ks': I.phys.ks, 'cn': I.phys.cn, 'cs': I.phys.cs, 'kr': 0.0, 'ktw': 0.0,
       'fn': I.phys.normalForce.norm(), 'fs': 0.0, 'tan_phi': I.phys.tangensOfFrictionAngle}
row = {k: str(v) for k, v in row.items()}
part = {'x': str(s.pos[0]), 'y': str(s.pos[1]), 'z': str(s.pos[2]), 'mass': str(s.mass),
        'inertia': str(s.inertia[0]), 'fixed': '0'}
K, C, m = ref.assemble('viscel', [part], [row], 'yade')
sc = 1.0 / ref.np.sqrt(m)
A = K * sc[:, None] * sc[None, :]
B = C * sc[:, None] * sc[None, :]
h_model = ref.damped_limit(0.5 * (A + A.T), B)
h_undamped = 2.0 / math.sqrt(ref.lam_max(0.5 * (A + A.T))[0])

rng = random.Random(3)
v0 = Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * 1e-7
w0 = Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * (1e-7 / R)

def ke():
    w = s.angVel
    return 0.5 * s.mass * s.vel.squaredNorm() + 0.5 * s.inertia[0] * w.squaredNorm()

def unstable(dt, nsteps=3000):
    O.loadTmp('rest')
    newton.damping = 0.0
    b = O.bodies[ball].state
    b.vel, b.angVel = v0, w0
    O.dt = dt
    e0 = 0.5 * b.mass * v0.squaredNorm() + 0.5 * b.inertia[0] * w0.squaredNorm()
    for k in range(nsteps // 50):
        O.run(50, True)
        w = b.angVel
        e = 0.5 * b.mass * b.vel.squaredNorm() + 0.5 * b.inertia[0] * w.squaredNorm()
        if not (e < 100 * e0):
            return True
    return False

lo, hi = 0.9 * h_model, 1.1 * h_model
assert not unstable(lo) and unstable(hi)
while (hi - lo) / lo > 1e-5:
    mid = 0.5 * (lo + hi)
    if unstable(mid):
        hi = mid
    else:
        lo = mid
lines = ['# output of yade_check_damped_single.py (Yade 2023.02a): one ViscElPhys sphere on a facet under gravity',
         'kn %.6g ks %.6g cn %.6g cs %.6g mass %.6g overlap %.3e' % (I.phys.kn, I.phys.ks, I.phys.cn, I.phys.cs, s.mass, g.penetrationDepth),
         'Yade measured limit [%.7e, %.7e] s (unstable: KE > 100 KE0 within 3000 steps)' % (lo, hi),
         'reference_damped.py: undamped %.7e s, exact damped %.7e s, ratio damped/measured-mid %.6f'
         % (h_undamped, h_model, h_model / (0.5 * (lo + hi)))]
print('\n'.join(lines))
with open(os.path.join(HERE, 'data', 'check_damped_single.txt'), 'w') as f:
    f.write('\n'.join(lines) + '\n')
