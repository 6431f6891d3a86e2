# Yade script (not plain Python): run as
#   yade -n -j1 -x yade_bonds.py [--quick] [--poly]
# A cemented sample: 108 equal spheres on a jittered fcc lattice (3 x 3 x 3
# cells, free, no walls), every neighbour pair within 1.1 (r1 + r2) joined by a
# CohFrictPhys bond (Ip2_CohFrictMat_CohFrictMat_CohFrictPhys with
# setCohesionNow, Law2_ScGeom6D_CohFrictPhys_CohesionMoment with the bending
# and twisting moments on, strengths far above any load: elastic), no damping,
# no gravity. The bonds are made at rest (each bond's plastic normal
# displacement unp set to its initial penetration depth, so no bond is loaded);
# the sample is exported in demstep's table formats and its largest stable
# step measured by bisection on kinetic-energy growth.
# With --poly the radii are R0 (1 +- 0.1) (uniform, seeded) and the detection
# factor 1.25: bonds between unequal spheres with gaps and overlaps, where
# Yade's shear kinematics (alpha on the translations, radii as arms) and its
# force's lever arms (to the contact point) differ.
# Output: data/bonded/ (or data/bonded_poly/){particles.txt,bonds.txt,bonds_yade.txt,summary.json,trials.csv}
import sys, os, json, math, random, time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import stability_search as search     # plain Python: the bisection
QUICK = '--quick' in sys.argv[1:]
POLY = '--poly' in sys.argv[1:]
CASE = 'bonded_poly' if POLY else 'bonded'
OUT = os.path.join(HERE, 'data', CASE)
os.makedirs(OUT, exist_ok=True)

R0 = 0.01            # m, every sphere
YOUNG = 1.0e7        # Pa: kn = E r = 1e5 N/m for two spheres of radius R0
POISSON = 0.3        # Yade's ks/kn ratio
ALPHA_KR = 2.0       # CohFrictMat defaults: kr = r1 r2 ks alphaKr
ALPHA_KTW = 2.0      #                       ktw = r1 r2 ks alphaKtw
DENSITY = 2623.0
FACTOR = 1.25 if POLY else 1.1   # interaction detection factor: bonds up to FACTOR (r1 + r2) apart
SPREAD = 0.1 if POLY else 0.0    # radii R0 (1 +- SPREAD)
JITTER = 0.04        # lattice positions moved by up to +- JITTER R0 per axis
STRONG = 1.0e30      # cohesion (Pa): no bond breaks or yields
V0 = 1.0e-7          # m/s, rms of the random test velocities (linear regime)
SEED = 7

mat = O.materials.append(CohFrictMat(young=YOUNG, poisson=POISSON, density=DENSITY,
                                     frictionAngle=math.atan(1.0e6), alphaKr=ALPHA_KR, alphaKtw=ALPHA_KTW,
                                     momentRotationLaw=True, isCohesive=True, normalCohesion=STRONG,
                                     shearCohesion=STRONG, etaRoll=-1.0, etaTwist=-1.0, label='mat'))

rng = random.Random(SEED)
a = 2.0 * R0 * math.sqrt(2.0)          # fcc cube edge for a nearest-neighbour distance 2 R0
basis = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
for i in range(3):
    for j in range(3):
        for k in range(3):
            for b in basis:
                c = Vector3(*[(n + o) * a + rng.uniform(-JITTER, JITTER) * R0
                              for n, o in zip((i, j, k), b)])
                radius = R0 * (1 + rng.uniform(-SPREAD, SPREAD)) if POLY else R0
                O.bodies.append(sphere(c, radius, material=mat))

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(aabbEnlargeFactor=FACTOR)], verletDist=0.05 * R0),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=FACTOR)],
                    [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)],
                    [Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]),
    NewtonIntegrator(damping=0.0, gravity=(0, 0, 0), label='newton'),
]
# one step of negligible length makes the bonds (the motion it causes is
# F/m dt^2 ~ 1e-38 m); then every bond is put at rest where it is
O.dt = 1.0e-20
O.step()
for inter in O.interactions:
    if inter.isReal:
        inter.phys.unp = inter.geom.penetrationDepth
        inter.phys.shearForce = Vector3(0, 0, 0)
for b in O.bodies:
    b.state.vel = Vector3(0, 0, 0)
    b.state.angVel = Vector3(0, 0, 0)
O.step()
fmax = max(O.forces.f(b.id).norm() for b in O.bodies)
tmax = max(O.forces.t(b.id).norm() for b in O.bodies)

# ---- export
ids = [b.id for b in O.bodies]
num_of = {bid: k + 1 for k, bid in enumerate(ids)}
with open(os.path.join(OUT, 'particles.txt'), 'w') as f:
    f.write('# Yade 2023.02a cemented sample "%s" (jittered fcc, CohFrictPhys bonds), at rest\n' % CASE)
    f.write('# x y z vx vy vz mass radius fixed inertia   (SI units)\n')
    for bid in ids:
        b = O.bodies[bid]
        p = b.state.pos
        f.write('%.17g %.17g %.17g 0 0 0 %.17g %.17g 0 %.17g\n'
                % (p[0], p[1], p[2], b.state.mass, b.shape.radius, b.state.inertia[0]))
bonds = []
for inter in O.interactions:
    if not inter.isReal:
        continue
    ph = inter.phys
    bonds.append((num_of[inter.id1], num_of[inter.id2], ph.kn, ph.ks, ph.kr, ph.ktw,
                  inter.geom.penetrationDepth, ph.cohesionBroken))
bonds.sort()
with open(os.path.join(OUT, 'bonds.txt'), 'w') as f:
    f.write('# Yade 2023.02a CohFrictPhys bonds of the cemented sample: i j (rows of particles.txt)\n')
    for c in bonds:
        f.write('%d %d\n' % c[:2])
with open(os.path.join(OUT, 'bonds_yade.txt'), 'w') as f:
    f.write('# Yade\'s own values per bond: i j kn ks kr ktw penetrationDepth (SI; ks without ScGeom\'s alpha)\n')
    for c in bonds:
        f.write('%d %d %.17g %.17g %.17g %.17g %.17g\n' % c[:7])

# ---- Yade's own estimates: PWaveTimeStep and GlobalStiffnessTimeStepper's raw value
O.saveTmp('rest')
pwave = PWaveTimeStep()
gsts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=1.0, timeStepUpdateInterval=1,
                                  maxDt=1.0, previousDt=1.0, defaultDt=1e-12, active=True)
# (no O.dt assignment here: assigning it switches the time stepper off)
O.engines = [gsts] + O.engines
O.step()
gsts_dt = O.dt
O.loadTmp('rest')

# ---- measured limit: bisection on kinetic-energy growth
rng = random.Random(SEED + 1)
vel0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * V0 for _ in ids]
ang0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * (V0 / R0) for _ in ids]


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
    O.loadTmp('rest')
    for k, bid in enumerate(ids):
        O.bodies[bid].state.vel = vel0[k]
        O.bodies[bid].state.angVel = ang0[k]
    O.dt = dt
    unstable, steps, ratio = search.grows(lambda n: O.run(n, True), kinetic, nmax, GROWTH)
    search.report(trials, dt, unstable, steps, ratio)
    return unstable


t0 = time.time()
# start from the bonded pair's fastest mode (bending, 2 kr/I for alphaKr = 2)
m = O.bodies[0].state.mass
inertia = O.bodies[0].state.inertia[0]
kn, ks = YOUNG * R0, POISSON * YOUNG * R0
w2 = max(2 * kn / m, 2 * ks * (1 / m + R0 ** 2 / inertia), 2 * R0 ** 2 * ks * ALPHA_KR / inertia)
dt = 2.0 / math.sqrt(w2)
RTOL = 1e-3 if QUICK else 1e-4
lo, hi = search.bisect(lambda d: trial(d, NMAX), dt, 1.1, RTOL)
lo, hi, confirm = search.confirm(lambda d: (trial(d, 5 * NMAX), trials[-1]['steps']), lo, hi, RTOL)

pen = [c[6] for c in bonds]
summary = {
    'case': CASE,
    'yade_version': '2023.02a',
    'n_particles': len(ids),
    'n_bonds': len(bonds),
    'bonds_broken': sum(1 for c in bonds if c[7]),
    'young': YOUNG, 'poisson_ks_over_kn': POISSON, 'alpha_kr': ALPHA_KR, 'alpha_ktw': ALPHA_KTW,
    'density': DENSITY, 'radius': R0, 'radius_spread': SPREAD, 'detection_factor': FACTOR,
    'jitter_over_r': JITTER,
    'radius_min': min(O.bodies[b].shape.radius for b in ids), 'radius_max': max(O.bodies[b].shape.radius for b in ids),
    'penetration_min': min(pen), 'penetration_max': max(pen),
    'largest_force_at_rest': fmax, 'largest_torque_at_rest': tmax,
    'GlobalStiffnessTimeStepper_raw': gsts_dt, 'PWaveTimeStep': pwave,
    'measured_dt_lo': lo, 'measured_dt_hi': hi, 'measured_dt_mid': 0.5 * (lo + hi),
    'criterion': 'unstable if kinetic energy (translational + rotational) exceeds %g x its initial value '
                 'within %d steps' % (GROWTH, NMAX),
    'confirmation_runs_at_lo': confirm,
    'trials': len(trials),
    'wall_time_s': time.time() - t0,
}
with open(os.path.join(OUT, 'summary.json'), 'w') as f:
    json.dump(summary, f, indent=1)
with open(os.path.join(OUT, 'trials.csv'), 'w') as f:
    f.write('dt,unstable,steps,ke_ratio_max\n')
    for t in trials:
        f.write('%.17g,%d,%d,%.6e\n' % (t['dt'], 1 if t['unstable'] else 0, t['steps'], t['ke_ratio_max']))
print(CASE + ': %d particles, %d bonds, measured [%.6e, %.6e], %.1f s'
      % (len(ids), len(bonds), lo, hi, time.time() - t0))
