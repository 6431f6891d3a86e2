# Yade script (not plain Python): run as
#   yade -n -j1 -x yade_clumps.py [--quick] [--build-only]
# A packing of clumps (two and three overlapping spheres) settled by gravity in
# a box of five walls (floor and four sides), linear FrictPhys law, rotations
# on. At the freeze gravity is replaced by constant forces that balance each
# member's contact force and torque (so the frozen state is an exact
# equilibrium and a run from it is the linearised motion), sliding is switched
# off, damping is 0. Exports the members, their contacts, the clump table and
# the walls in demstep's formats, records Yade's GlobalStiffnessTimeStepper
# (raw) and measures the largest stable step by bisection on kinetic-energy
# growth. Output: data/clumps/{particles.txt, contacts.txt, bodies.txt,
# walls.json, summary.json, trials.csv}
import sys, os, json, math, random, time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import stability_search as search     # plain Python: the bisection
QUICK = '--quick' in sys.argv
BUILD_ONLY = '--build-only' in sys.argv
OUT = os.path.join(HERE, 'data', 'clumps')
os.makedirs(OUT, exist_ok=True)

R0 = 0.01            # m, member radius
KN0 = 1.0e5          # N/m, k_n between two members
KS_RATIO = 0.3       # k_s / k_n (FrictMat.poisson for FrictPhys)
YOUNG = KN0 / R0
DENSITY = 2623.0
NOSLIP = 1.0e6
V0 = 1.0e-6          # m/s, rms of the test velocities
SEED = 12345
NX, NY, NZ = 4, 4, 3  # clumps on a grid before they fall
GAP = 3.2 * R0        # grid spacing
L = NX * GAP          # box side (x and y)

mat = O.materials.append(FrictMat(young=YOUNG, poisson=KS_RATIO, density=DENSITY,
                                  frictionAngle=math.atan(0.5), label='mat'))
walls = [((0, 0, 0), 2, (0, 0, 1)), ((0, 0, 0), 0, (1, 0, 0)), ((L, 0, 0), 0, (-1, 0, 0)),
         ((0, 0, 0), 1, (0, 1, 0)), ((0, L, 0), 1, (0, -1, 0))]
wall_ids = []
for p, axis, nrm in walls:
    wall_ids.append(O.bodies.append(wall(Vector3(*p), axis, material=mat)))

rng = random.Random(7)
clumps = []
for k in range(NZ):
    for j in range(NY):
        for i in range(NX):
            c = Vector3((i + 0.5) * GAP, (j + 0.5) * GAP, R0 * 1.5 + k * GAP)
            nm = 2 + (i + j + k) % 2
            # members 1.2 R0 apart (overlapping) in a random orientation
            u = Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)).normalized()
            v = u.cross(Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))).normalized()
            pts = [c - 0.6 * R0 * u, c + 0.6 * R0 * u]
            if nm == 3:
                pts.append(c + 1.04 * R0 * v)
            cid, mids = O.bodies.appendClumped([sphere(p, R0, material=mat) for p in pts])
            clumps.append((cid, list(mids)))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()], verletDist=0.05 * R0),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
                    [Ip2_FrictMat_FrictMat_FrictPhys()],
                    [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.4, gravity=(0, 0, -9.81), label='newton'),
]
O.dt = 0.3 * PWaveTimeStep()
t0 = time.time()
# settle: until the forces balance
for it in range(400):
    O.run(1000, True)
    if unbalancedForce() < 1e-4:
        break
print('settled: unbalanced force %.2e after %d steps, %.1f s' % (unbalancedForce(), O.iter, time.time() - t0))

# ---- freeze: no damping, no gravity, no sliding, zero velocities
newton.damping = 0.0
newton.gravity = Vector3(0, 0, 0)
for i in O.interactions:
    if i.isReal:
        i.phys.tangensOfFrictionAngle = NOSLIP
O.materials[mat].frictionAngle = math.atan(NOSLIP)
for cid, mids in clumps:
    O.bodies[cid].state.vel = Vector3(0, 0, 0)
    O.bodies[cid].state.angVel = Vector3(0, 0, 0)
# the contact forces at the frozen state, without moving: one step at a tiny dt
O.dt = 1e-20
O.step()
members = [m for cid, mids in clumps for m in mids]
balance = {m: (-O.forces.f(m), -O.forces.t(m)) for m in members}

def restore():
    # a saved state does not keep the permanent forces: set them again
    O.loadTmp('frozen')
    for m in members:
        O.forces.setPermF(m, balance[m][0])
        O.forces.setPermT(m, balance[m][1])
O.dt = 1e-12

# ---- export: members (1-based rows), contacts, clumps, walls
row = {m: k + 1 for k, m in enumerate(members)}
body_of = {}
for b, (cid, mids) in enumerate(clumps):
    for m in mids:
        body_of[m] = b + 1
with open(os.path.join(OUT, 'particles.txt'), 'w') as f:
    f.write('# Yade 2023.02a clump members, settled and frozen (velocities 0)\n')
    f.write('# x y z vx vy vz mass radius fixed inertia   (SI units)\n')
    for m in members:
        b = O.bodies[m]
        p = b.state.pos
        mass = DENSITY * 4.0 / 3.0 * math.pi * b.shape.radius ** 3
        f.write('%.17g %.17g %.17g 0 0 0 %.17g %.17g 0 %.17g\n'
                % (p[0], p[1], p[2], mass, b.shape.radius, 0.4 * mass * b.shape.radius ** 2))
with open(os.path.join(OUT, 'bodies.txt'), 'w') as f:
    f.write('# particle body   (rows of particles.txt; one body per Yade clump)\n')
    for m in members:
        f.write('%d %d\n' % (row[m], body_of[m]))
contacts, wall_k, ov = [], [], []
for i in O.interactions:
    if not i.isReal:
        continue
    ov.append(i.geom.penetrationDepth)
    if i.id1 in wall_ids or i.id2 in wall_ids:
        wall_k.append((i.phys.kn, i.phys.ks))
        continue
    a, b = sorted((row[i.id1], row[i.id2]))
    contacts.append((a, b, i.phys.kn, i.phys.ks))
contacts.sort()
with open(os.path.join(OUT, 'contacts.txt'), 'w') as f:
    f.write('# Yade 2023.02a real interactions between members of different clumps (FrictPhys)\n')
    f.write('# i j k_n k_t   (rows of particles.txt; N/m)\n')
    for c in contacts:
        f.write('%d %d %.17g %.17g\n' % c)
wall_kn = sorted(set(k[0] for k in wall_k))
wall_ks = sorted(set(k[1] for k in wall_k))
with open(os.path.join(OUT, 'walls.json'), 'w') as f:
    json.dump({'points': [list(p) for p, a, n in walls], 'normals': [list(n) for p, a, n in walls],
               'k_n': wall_kn, 'k_t': wall_ks, 'n_wall_contacts': len(wall_k)}, f, indent=1)
clump_mass = [O.bodies[cid].state.mass for cid, mids in clumps]
clump_inertia = [list(O.bodies[cid].state.inertia) for cid, mids in clumps]

# ---- Yade's own estimate (raw)
O.dt = 1e-12
O.saveTmp('frozen')
gsts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=1.0, timeStepUpdateInterval=1,
                                  maxDt=1.0, previousDt=1.0, defaultDt=1e-12, active=True)
O.engines = [gsts] + O.engines
O.step()
gsts_dt = O.dt
restore()
pwave = PWaveTimeStep()

def kinetic():
    e = 0.0
    for cid, mids in clumps:
        s = O.bodies[cid].state
        w = s.ori.conjugate() * s.angVel     # body axes, where s.inertia is diagonal
        e += 0.5 * s.mass * s.vel.squaredNorm()
        e += 0.5 * (s.inertia[0] * w[0] ** 2 + s.inertia[1] * w[1] ** 2 + s.inertia[2] * w[2] ** 2)
    return e

# the balance: from rest at half Yade's estimate, the kinetic energy after 2000
# steps (the test runs start from about 1e-14 J)
O.dt = 0.5 * gsts_dt
O.run(2000, True)
ke_rest = kinetic()
print('clumps %d, members %d, contacts %d (+%d on walls), GSTS raw %.6e, PWave %.6e, KE from rest %.3e J'
      % (len(clumps), len(members), len(contacts), len(wall_k), gsts_dt, pwave, ke_rest))
if BUILD_ONLY:
    sys.exit(0)

# ---- bisection on kinetic-energy growth
rng = random.Random(SEED)
vel0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * V0 for _ in clumps]
ang0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * (V0 / R0) for _ in clumps]

GROWTH = 1.0e3
NMAX = 4000 if QUICK else 20000
trials = []

def trial(dt, nmax):
    restore()
    for k, (cid, mids) in enumerate(clumps):
        O.bodies[cid].state.vel = vel0[k]
        O.bodies[cid].state.angVel = ang0[k]
    O.dt = dt
    unstable, steps, ratio = search.grows(lambda n: O.run(n, True), kinetic, nmax, GROWTH)
    search.report(trials, dt, unstable, steps, ratio)
    return unstable

RTOL = 1e-3 if QUICK else 1e-4
lo, hi = search.bisect(lambda d: trial(d, NMAX), gsts_dt, 1.03, RTOL)
lo, hi, confirm = search.confirm(lambda d: (trial(d, 5 * NMAX), trials[-1]['steps']), lo, hi, RTOL)

summary = {
    'case': 'clumps', 'yade_version': '2023.02a',
    'n_clumps': len(clumps), 'n_members': len(members), 'n_contacts': len(contacts),
    'n_wall_contacts': len(wall_k), 'wall_k_n': wall_kn, 'wall_k_t': wall_ks,
    'density': DENSITY, 'young': YOUNG, 'poisson_ks_over_kn': KS_RATIO, 'radius': R0,
    'member_offset': '1.2 R0 apart (pairs); a third member 1.04 R0 from the centre',
    'overlap_min': min(ov), 'overlap_max': max(ov), 'overlap_mean': sum(ov) / len(ov),
    'clump_mass': clump_mass, 'clump_principal_inertia': clump_inertia,
    'measured_dt_lo': lo, 'measured_dt_hi': hi, 'measured_dt_mid': 0.5 * (lo + hi),
    'criterion': 'unstable if the clumps\' kinetic energy exceeds %g x its initial value within %d steps'
                 % (GROWTH, NMAX),
    'confirmation_runs_at_lo': confirm,
    'test_velocity_rms_per_component': V0, 'seed': SEED,
    'GlobalStiffnessTimeStepper_raw': gsts_dt, 'PWaveTimeStep': pwave,
    'kinetic_energy_from_rest_2000_steps_at_half_gsts': ke_rest,
    'wall_time_s': time.time() - t0,
}
with open(os.path.join(OUT, 'summary.json'), 'w') as f:
    json.dump(summary, f, indent=1)
with open(os.path.join(OUT, 'trials.csv'), 'w') as f:
    f.write('dt,unstable,steps,ke_ratio_max\n')
    for t in trials:
        f.write('%.10e,%d,%d,%.6e\n' % (t['dt'], t['unstable'], t['steps'], t['ke_ratio_max']))
print(json.dumps({k: summary[k] for k in ('measured_dt_lo', 'measured_dt_hi', 'GlobalStiffnessTimeStepper_raw')}))
