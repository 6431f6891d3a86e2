# Yade script (not plain Python): run as
#   yade -n -j1 -x yade_stability.py CASE [--quick] [--build-only]
# CASE is sc, fcc or random. Builds the periodic assembly with the linear
# FrictPhys law (no damping, rotations on, gravity 0, no sliding), freezes it,
# exports particles and contacts in demstep's table formats, records Yade's own
# time-step estimates (GlobalStiffnessTimeStepper, PWaveTimeStep) and measures
# the largest stable step by bisection on kinetic-energy growth.
# Output: data/CASE/{particles.txt,contacts.txt,cell.json,summary.json,trials.csv}
import sys, os, json, math, random, time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import stability_search as search     # plain Python: the bisection
args = [a for a in sys.argv[1:]]
if not args or args[0] not in ('sc', 'fcc', 'random'):
    print('usage: yade -n -j1 -x yade_stability.py sc|fcc|random [--quick]')
    sys.exit(2)
CASE = args[0]
QUICK = '--quick' in args
BUILD_ONLY = '--build-only' in args
OUT = os.path.join(HERE, 'data', CASE)
os.makedirs(OUT, exist_ok=True)

# ---- material: k_n = E R for two equal spheres (2 E R E R / (E R + E R)),
# k_s = poisson * k_n (FrictMat.poisson is the ks/kn ratio for FrictPhys).
R0 = 0.01            # m, lattice radius / mean radius of the random packing
KN0 = 1.0e5          # N/m, k_n between two spheres of radius R0
KS_RATIO = 0.3       # k_s / k_n  -> k_s = 3e4 N/m for R0 pairs
YOUNG = KN0 / R0     # Pa
# density chosen so that the SC lattice's 6-DOF limit sits at the figure
# (2.6206e-4 s); see README.md "Choice of density".
DENSITY = float(os.environ.get('DEMSTEP_YADE_DENSITY', '2623.0'))
OVERLAP = 1.0e-3     # lattices: overlap / (2 R0), spacing = 2 R0 (1 - OVERLAP)
NOSLIP = 1.0e6       # tan(friction angle) set on every contact: no sliding

V0 = 1.0e-7          # m/s, rms of the random test velocities (tiny: linear regime)
SEED = 12345

mat = O.materials.append(FrictMat(young=YOUNG, poisson=KS_RATIO, density=DENSITY,
                                  frictionAngle=math.atan(NOSLIP), label='mat'))

def engines(damping):
    return [
        ForceResetter(),
        InsertionSortCollider([Bo1_Sphere_Aabb()], verletDist=0.05 * R0),
        InteractionLoop([Ig2_Sphere_Sphere_ScGeom()],
                        [Ip2_FrictMat_FrictMat_FrictPhys()],
                        [Law2_ScGeom_FrictPhys_CundallStrack()]),
        NewtonIntegrator(damping=damping, gravity=(0, 0, 0), label='newton'),
    ]

def lattice(kind):
    a_sc = 2 * R0 * (1 - OVERLAP)
    if kind == 'sc':
        n = 6
        basis = [(0, 0, 0)]
        a = a_sc
    else:
        n = 4
        basis = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
        a = a_sc * math.sqrt(2)    # nearest neighbour distance a/sqrt(2)
    L = n * a
    O.periodic = True
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    for i in range(n):
        for j in range(n):
            for k in range(n):
                for b in basis:
                    c = Vector3((i + b[0] + 0.25) * a, (j + b[1] + 0.25) * a, (k + b[2] + 0.25) * a)
                    O.bodies.append(sphere(c, R0, material=mat))
    O.engines = engines(0.0)
    O.dt = 1e-6
    O.step()          # create the contacts (exact symmetry: no net forces)
    O.step()

def random_packing():
    from yade import pack
    num = 600
    # cell of volume num * mean sphere volume / 0.64 (a dense random packing)
    rvol = 4.0 / 3.0 * math.pi * R0 ** 3 * (1 + 0.2 ** 2)   # <r^3> for r uniform in R0 (1 +- 0.2)
    L = (num * rvol / 0.60) ** (1.0 / 3.0)
    O.periodic = True
    O.cell.hSize = Matrix3(L, 0, 0, 0, L, 0, 0, 0, L)
    sp = pack.SpherePack()
    # start loose, grow to jamming
    sp.makeCloud((0, 0, 0), (L, L, L), rMean=0.75 * R0, rRelFuzz=0.2, num=num, periodic=True, seed=1)
    sp.toSimulation(material=mat)
    O.engines = engines(0.5)
    # frictionless growth (no shear pre-load at the end), then no-slip
    O.materials[mat].frictionAngle = 0.0
    O.dt = 0.5 * PWaveTimeStep()
    target = 2.0e-3   # mean overlap / mean radius of the relaxed packing (lattices: 2e-3)

    def state():
        ov = [i.geom.penetrationDepth / (0.5 * (i.geom.refR1 + i.geom.refR2))
              for i in O.interactions if i.isReal]
        return (sum(ov) / len(ov) if ov else 0.0), 2.0 * len(ov) / len(O.bodies)
    grown = 1.0
    # 1) fast growth until a contact network spans the cell (dynamic compression)
    for it in range(5000):
        O.run(100, True)
        mean_ov, z = state()
        if z > 4.0:
            break
        growParticles(1.003, updateMass=True, dynamicOnly=True)
        grown *= 1.003
    # 2) quasi-static growth: relax, then grow towards the target overlap
    for it in range(400):
        O.run(2000, True)
        mean_ov, z = state()
        if mean_ov >= target and z > 5.0 and unbalancedForce() < 0.05:
            break
        f = 1.0 + min(2e-3, max(2e-4, 0.5 * (target - mean_ov)))
        growParticles(f, updateMass=True, dynamicOnly=True)
        grown *= f
    print('growth: factor %.5f, mean overlap/r %.3e, z %.3f, steps %d' % (grown, mean_ov, z, O.iter))
    # Ip2 set k_n, k_s when each contact formed; growth changed the radii since:
    # give every contact the FrictPhys values of its final radii
    for i in O.interactions:
        if i.isReal:
            r1, r2 = O.bodies[i.id1].shape.radius, O.bodies[i.id2].shape.radius
            i.phys.kn = 2 * YOUNG * r1 * YOUNG * r2 / (YOUNG * r1 + YOUNG * r2)
            i.phys.ks = KS_RATIO * i.phys.kn
    # 3) relax at fixed radii with damping until forces balance
    for it in range(1000):
        O.run(200, True)
        if unbalancedForce() < 1e-6:
            break
    print('relaxed: unbalanced force %.2e after %d steps' % (unbalancedForce(), O.iter))

t0 = time.time()
if CASE in ('sc', 'fcc'):
    lattice(CASE)
else:
    random_packing()

# ---- freeze: no damping, no sliding, zero velocities
newton.damping = 0.0
for i in O.interactions:
    if i.isReal:
        i.phys.tangensOfFrictionAngle = NOSLIP
for b in O.bodies:
    b.state.vel = Vector3(0, 0, 0)
    b.state.angVel = Vector3(0, 0, 0)
O.materials[mat].frictionAngle = math.atan(NOSLIP)
unb = unbalancedForce()

# ---- export (positions wrapped into the cell)
L = [O.cell.hSize[0, 0], O.cell.hSize[1, 1], O.cell.hSize[2, 2]]
ids = [b.id for b in O.bodies]
num_of = {bid: k + 1 for k, bid in enumerate(ids)}     # 1-based row numbers
cellhdr = '# cell_lo = 0 0 0\n# cell_hi = %.17g %.17g %.17g\n# periodic = T T T\n' % tuple(L)
with open(os.path.join(OUT, 'particles.txt'), 'w') as f:
    f.write('# Yade 2023.02a periodic assembly "%s", exported frozen (velocities 0)\n' % CASE)
    f.write(cellhdr)
    f.write('# x y z vx vy vz mass radius fixed inertia   (SI units)\n')
    for bid in ids:
        b = O.bodies[bid]
        p = O.cell.wrap(b.state.pos)
        f.write('%.17g %.17g %.17g 0 0 0 %.17g %.17g 0 %.17g\n'
                % (p[0], p[1], p[2], b.state.mass, b.shape.radius, b.state.inertia[0]))
contacts = []
for i in O.interactions:
    if not i.isReal:
        continue
    contacts.append((num_of[i.id1], num_of[i.id2], i.phys.kn, i.phys.ks,
                     i.geom.penetrationDepth, i.phys.normalForce.norm()))
contacts.sort()
with open(os.path.join(OUT, 'contacts.txt'), 'w') as f:
    f.write('# Yade 2023.02a real interactions of assembly "%s" (FrictPhys)\n' % CASE)
    f.write(cellhdr)
    f.write('# i j k_n k_t   (particle numbers as rows of particles.txt; N/m)\n')
    for c in contacts:
        f.write('%d %d %.17g %.17g\n' % c[:4])
with open(os.path.join(OUT, 'cell.json'), 'w') as f:
    json.dump({'cell_lo': [0.0, 0.0, 0.0], 'cell_hi': L, 'periodic': [True, True, True]}, f, indent=1)

# ---- Yade's own estimates
pwave = PWaveTimeStep()
O.saveTmp('frozen')
gsts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=1.0, timeStepUpdateInterval=1,
                                  maxDt=1.0, previousDt=1.0, defaultDt=1e-12, active=True)
O.engines = [gsts] + O.engines
O.dt = 1e-12
O.step()
gsts_dt = O.dt     # raw value: sqrt(2) min_bodies sqrt(min(m/max_diag K, I/diag K_rot))
O.loadTmp('frozen')

if BUILD_ONLY:
    print('built %s: %d particles, %d contacts, GSTS %.6e, PWave %.6e, unbalanced %.2e, %.1f s'
          % (CASE, len(ids), len(contacts), gsts_dt, pwave, unb, time.time() - t0))
    sys.exit(0)

# ---- measured limit: bisection on kinetic-energy growth
rng = random.Random(SEED)
vel0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) for _ in ids]
ang0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) for _ in ids]
ncontacts = {bid: 0 for bid in ids}
for c in O.interactions:
    if c.isReal:
        ncontacts[c.id1] += 1
        ncontacts[c.id2] += 1
mv = Vector3(0, 0, 0)
for k, bid in enumerate(ids):       # zero net momentum
    mv += vel0[k]
mv /= len(ids)
for k in range(len(ids)):
    vel0[k] = (vel0[k] - mv) * V0
    ang0[k] = ang0[k] * (V0 / R0)

def kinetic():
    e = 0.0
    for b in O.bodies:
        e += 0.5 * b.state.mass * b.state.vel.squaredNorm()
        w = b.state.angVel
        e += 0.5 * (b.state.inertia[0] * w[0] ** 2 + b.state.inertia[1] * w[1] ** 2 + b.state.inertia[2] * w[2] ** 2)
    return e

GROWTH = 1.0e3
NMAX = 4000 if QUICK else 20000
trials = []

def trial(dt, nmax):
    O.loadTmp('frozen')
    for k, bid in enumerate(ids):
        b = O.bodies[bid]
        if ncontacts[bid] == 0:       # rattler: no stiffness, leave it at rest
            continue
        b.state.vel = vel0[k]
        b.state.angVel = ang0[k]
    O.dt = dt
    unstable, steps, ratio = search.grows(lambda n: O.run(n, True), kinetic, nmax, GROWTH)
    search.report(trials, dt, unstable, steps, ratio)
    return unstable

# bracket: start at GlobalStiffnessTimeStepper's raw value, widen by 1.03;
# then confirm the stable end with a run 5 times longer, stepping down while it fails
RTOL = 1e-3 if QUICK else 1e-4
lo, hi = search.bisect(lambda d: trial(d, NMAX), gsts_dt, 1.03, RTOL)
lo, hi, confirm = search.confirm(lambda d: (trial(d, 5 * NMAX), trials[-1]['steps']), lo, hi, RTOL)

ov = [c[4] for c in contacts]
summary = {
    'case': CASE,
    'yade_version': '2023.02a',
    'n_particles': len(ids),
    'n_contacts': len(contacts),
    'n_rattlers': sum(1 for bid in ids if ncontacts[bid] == 0),
    'mean_coordination': 2.0 * len(contacts) / len(ids),
    'cell_hi': L,
    'density': DENSITY, 'young': YOUNG, 'poisson_ks_over_kn': KS_RATIO,
    'radius_min': min(O.bodies[b].shape.radius for b in ids),
    'radius_max': max(O.bodies[b].shape.radius for b in ids),
    'overlap_min': min(ov), 'overlap_max': max(ov), 'overlap_mean': sum(ov) / len(ov),
    'unbalanced_force_at_freeze': unb,
    'measured_dt_lo': lo, 'measured_dt_hi': hi, 'measured_dt_mid': 0.5 * (lo + hi),
    'criterion': 'unstable if kinetic energy (translational + rotational) exceeds %g x its initial value within %d steps'
                 % (GROWTH, NMAX),
    'confirmation_runs_at_lo': confirm,
    'test_velocity_rms_per_component': V0, 'test_angvel_rms_per_component': V0 / R0, 'seed': SEED,
    'GlobalStiffnessTimeStepper_raw': gsts_dt,
    'PWaveTimeStep': pwave,
    'wall_time_s': time.time() - t0,
}
with open(os.path.join(OUT, 'summary.json'), 'w') as f:
    json.dump(summary, f, indent=1)
with open(os.path.join(OUT, 'trials.csv'), 'w') as f:
    f.write('dt,unstable,steps,ke_ratio_max\n')
    for t in trials:
        f.write('%.10e,%d,%d,%.6e\n' % (t['dt'], t['unstable'], t['steps'], t['ke_ratio_max']))
print(json.dumps(summary, indent=1))
