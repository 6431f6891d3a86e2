# Yade script (not plain Python): run as
#   yade -n -j1 -x yade_damped.py SCENE [--v0=X] [--per-particle] [--quench=N] [--noslip]
#                                       [--quick] [--build-only]
# SCENE is
#   viscel   ViscElPhys spheres (en = et = 0.5, contact time tc) poured into a
#            box of fixed facets under gravity, settled;
#   cohfrict CohFrictPhys spheres with rolling and twisting stiffness
#            (momentRotationLaw, alphaKr, alphaKtw), friction, no cohesion,
#            poured into the same box, settled.
# The settled state is saved, exported (particles, interactions, facets) and the
# largest stable step is bisected on kinetic-energy growth from a perturbed copy
# of that state with NewtonIntegrator.damping = 0 (criterion in README.md).
# Output: data/SCENE/{particles.csv,interactions.csv,facets.csv,measured.csv,
#                     summary.json, and per test amplitude V0 and criterion:
#                     trials_v0_*.csv, summary_v0_*.json}
# (viscel with --quench=0 writes data/viscel_creeping, --noslip adds _noslip)
import sys, os, json, math, random, time

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
sys.path.insert(0, HERE)
import stability_search as search     # plain Python: the bisection
args = sys.argv[1:]
SCENES = ('viscel', 'cohfrict')
if not args or args[0] not in SCENES:
    print('usage: yade -n -j1 -x yade_damped.py viscel|cohfrict [--v0=X] [--per-particle] '
          '[--quench=N] [--noslip] [--quick] [--build-only]')
    sys.exit(2)
SCENE = args[0]
QUICK = '--quick' in args
BUILD_ONLY = '--build-only' in args
# rms of the random test velocity (m/s per component; angular: V0 / radius)
V0 = 1.0e-5
for a in args:
    if a.startswith('--v0='):
        V0 = float(a[5:])
# --per-particle: a trial is unstable when some sphere's kinetic energy exceeds
# GROWTH_PP times its own largest value in the small-step run (or its initial
# value); for piles that creep, where the total kinetic energy of the creep hides
# a localized unstable mode that saturates (contacts opening) below it
PER_PARTICLE = '--per-particle' in args
GROWTH_PP = 1.0e4
TAG = 'v0_%.0e' % V0 + ('_pp' if PER_PARTICLE else '')
# quench rounds after settling (all velocities set to 0, then 1000 damped steps):
# ViscElPhys has no rolling resistance, so spheres keep rolling in a pile that
# looks settled; quenching removes that energy (it does not stop the creep
# altogether, see README.md). Default 60 for viscel, 0 for cohfrict.
QUENCH = 60 if SCENE == 'viscel' else 0
for a in args:
    if a.startswith('--quench='):
        QUENCH = int(a[9:])
# --noslip: at the freeze every contact gets tan(phi) = 1e6 (no Coulomb sliding
# during the measurement; the settled state is the same)
NOSLIP = '--noslip' in args
OUT = os.path.join(HERE, 'data', (SCENE if not (SCENE == 'viscel' and QUENCH == 0) else 'viscel_creeping')
                   + ('_noslip' if NOSLIP else ''))
os.makedirs(OUT, exist_ok=True)

# ---------------------------------------------------------------- the scene
RADII = (0.004, 0.005, 0.006)     # m, three sizes, drawn with equal probability
DENSITY = 2500.0                  # kg/m^3
BOX = (0.07, 0.07, 0.17)          # m, inner size of the facet box (x, y, z), floor at z = 0
NX, NZ = 5, 12                    # loose grid: NX x NX x NZ = 300 sphere centres
GRAVITY = (0.0, 0.0, -9.81)
SEED_PACK = 7
FRICTION = 0.5                    # rad, friction angle of both materials
# ViscElMat: contact time and restitution (Pournin's formulas, see CONVENTIONS_DAMPING.md)
TC, EN, ET = 2.0e-4, 0.5, 0.5
# CohFrictMat: kn = E r for equal spheres, ks = poisson kn, kr = alphaKr ks r1 r2, ktw = alphaKtw ks r1 r2
YOUNG, POISSON, ALPHA_KR, ALPHA_KTW = 2.0e7, 0.3, 2.0, 1.0
SETTLE_DAMPING = 0.3              # NewtonIntegrator local damping while settling only
SETTLE_UNBALANCED = 1e-4          # settled: Yade's unbalancedForce() below this ...
SETTLE_KE = 1e-9                  # ... and kinetic energy below this (J)

if SCENE == 'viscel':
    mat = O.materials.append(ViscElMat(tc=TC, en=EN, et=ET, density=DENSITY,
                                       frictionAngle=FRICTION, label='mat'))
else:
    mat = O.materials.append(CohFrictMat(young=YOUNG, poisson=POISSON, density=DENSITY,
                                         frictionAngle=FRICTION, isCohesive=False,
                                         momentRotationLaw=True, alphaKr=ALPHA_KR,
                                         alphaKtw=ALPHA_KTW, etaRoll=-1.0, etaTwist=-1.0,
                                         label='mat'))

facet_ids = O.bodies.append(geom.facetBox((0.5 * BOX[0], 0.5 * BOX[1], 0.5 * BOX[2]),
                                          (0.5 * BOX[0], 0.5 * BOX[1], 0.5 * BOX[2]),
                                          wallMask=63, material=mat, fixed=True))
rng = random.Random(SEED_PACK)
sphere_ids = []
pitch = BOX[0] / NX
for k in range(NZ):
    for j in range(NX):
        for i in range(NX):
            r = rng.choice(RADII)
            c = Vector3((i + 0.5) * pitch + rng.uniform(-1e-3, 1e-3),
                        (j + 0.5) * pitch + rng.uniform(-1e-3, 1e-3),
                        (k + 0.5) * pitch)
            sphere_ids.append(O.bodies.append(sphere(c, r, material=mat)))

if SCENE == 'viscel':
    ig2 = [Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()]
    ip2 = [Ip2_ViscElMat_ViscElMat_ViscElPhys()]
    law = [Law2_ScGeom_ViscElPhys_Basic()]
else:
    ig2 = [Ig2_Sphere_Sphere_ScGeom6D(), Ig2_Facet_Sphere_ScGeom6D()]
    ip2 = [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()]
    law = [Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=True,
                                                      useIncrementalForm=False, label='law')]
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()], verletDist=0.1 * min(RADII)),
    InteractionLoop(ig2, ip2, law),
    NewtonIntegrator(damping=SETTLE_DAMPING, gravity=GRAVITY, label='newton'),
]

def kinetic():
    e = 0.0
    for bid in sphere_ids:
        s = O.bodies[bid].state
        e += 0.5 * s.mass * s.vel.squaredNorm()
        w = s.angVel
        e += 0.5 * (s.inertia[0] * w[0] ** 2 + s.inertia[1] * w[1] ** 2 + s.inertia[2] * w[2] ** 2)
    return e

t0 = time.time()
O.dt = 0.3 * PWaveTimeStep() if SCENE == 'cohfrict' else 0.05 * TC
settle_dt = O.dt
# ---------------------------------------------------------------- settle
settle_log = []
for it in range(200):
    O.run(2000, True)
    ke, unb = kinetic(), unbalancedForce()
    settle_log.append((O.iter, O.time, ke, unb))
    print('settle: iter %d t %.3f s KE %.3e J unbalanced %.3e' % (O.iter, O.time, ke, unb))
    sys.stdout.flush()
    if O.time > 0.5 and unb < SETTLE_UNBALANCED and ke < SETTLE_KE:
        break
    if QUENCH > 0 and O.time > 1.5:
        break
for q in range(QUENCH):
    for bid in sphere_ids:
        O.bodies[bid].state.vel = Vector3(0, 0, 0)
        O.bodies[bid].state.angVel = Vector3(0, 0, 0)
    O.run(1000, True)
    ke, unb = kinetic(), unbalancedForce()
    settle_log.append((O.iter, O.time, ke, unb))
    print('quench %d: iter %d KE %.3e J unbalanced %.3e' % (q, O.iter, ke, unb))
    sys.stdout.flush()
# freeze: velocities 0, local damping 0, forces recomputed for that state
newton.damping = 0.0
if NOSLIP:
    O.materials[mat].frictionAngle = math.atan(1e6)
    for I in O.interactions:
        if I.isReal:
            I.phys.tangensOfFrictionAngle = 1e6
for bid in sphere_ids:
    O.bodies[bid].state.vel = Vector3(0, 0, 0)
    O.bodies[bid].state.angVel = Vector3(0, 0, 0)
O.run(1, True)     # forces consistent with zero velocities
for bid in sphere_ids:
    O.bodies[bid].state.vel = Vector3(0, 0, 0)
    O.bodies[bid].state.angVel = Vector3(0, 0, 0)
unb = unbalancedForce()
O.saveTmp('settled')
O.save(os.path.join('/tmp', 'demstep_yade_%s_settled.yade.gz' % SCENE))
print('settled after %d steps, %.1f s wall; unbalanced force %.3e' % (O.iter, time.time() - t0, unb))

# ---------------------------------------------------------------- export
row_of = {bid: k for k, bid in enumerate(sphere_ids)}        # 0-based sphere rows
wall_of = {fid: k for k, fid in enumerate(facet_ids)}        # 0-based facet rows
with open(os.path.join(OUT, 'particles.csv'), 'w') as f:
    f.write('# Yade 2023.02a scene "%s", settled state (velocities set to 0); SI units; '
            'inertia = principal moment (Yade State.inertia[0]); fixed 0/1\n' % SCENE)
    f.write('row,yade_id,x,y,z,radius,mass,inertia,fixed\n')
    for bid in sphere_ids:
        b = O.bodies[bid]
        p = b.state.pos
        f.write('%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n'
                % (row_of[bid], bid, p[0], p[1], p[2], b.shape.radius, b.state.mass,
                   b.state.inertia[0], 1 if b.state.blockedDOFs == 'xyzXYZ' else 0))
with open(os.path.join(OUT, 'facets.csv'), 'w') as f:
    f.write('# fixed Facet bodies of the box (global vertex coordinates, m); they are ground\n')
    f.write('wall,yade_id,ax,ay,az,bx,by,bz,cx,cy,cz,nx,ny,nz\n')
    for fid in facet_ids:
        b = O.bodies[fid]
        vs = [b.state.pos + b.state.ori * v for v in b.shape.vertices]
        nrm = (vs[1] - vs[0]).cross(vs[2] - vs[0])
        nrm = nrm / nrm.norm()
        f.write('%d,%d,%s,%.17g,%.17g,%.17g\n'
                % (wall_of[fid], fid, ','.join('%.17g' % x for v in vs for x in v), nrm[0], nrm[1], nrm[2]))

n_sliding = 0
rows = []
for I in O.interactions:
    if not I.isReal:
        continue
    g, ph = I.geom, I.phys
    a, b = I.id1, I.id2
    kind1 = 'w' if a in wall_of else 'p'
    kind2 = 'w' if b in wall_of else 'p'
    i1 = wall_of[a] if kind1 == 'w' else row_of[a]
    i2 = wall_of[b] if kind2 == 'w' else row_of[b]
    fn = ph.normalForce.norm()
    fs = ph.shearForce.norm()
    mu = ph.tangensOfFrictionAngle
    sliding = 1 if fs >= (1 - 1e-6) * mu * fn else 0
    n_sliding += sliding
    if SCENE == 'viscel':
        cn, cs, kr, ktw, mb, mt = ph.cn, ph.cs, 0.0, 0.0, 0.0, 0.0
    else:
        cn, cs, kr, ktw = 0.0, 0.0, ph.kr, ph.ktw
        mb, mt = ph.moment_bending.norm(), ph.moment_twist.norm()
    rows.append((kind1, i1, kind2, i2, g.normal, g.contactPoint, g.penetrationDepth,
                 g.refR1, g.refR2, ph.kn, ph.ks, cn, cs, kr, ktw, fn, fs, mu, sliding, mb, mt))
rows.sort(key=lambda r: (r[0] != 'w', r[1], r[2] != 'w', r[3]))
with open(os.path.join(OUT, 'interactions.csv'), 'w') as f:
    f.write('# real interactions of the settled state; kind w = facet (row of facets.csv), p = sphere '
            '(row of particles.csv); normal points from body 1 to body 2; contact point and '
            'refR1/refR2 as Yade ScGeom holds them; SI units; sliding = 1 if |Fs| >= mu Fn\n')
    f.write('kind1,i1,kind2,i2,nx,ny,nz,cpx,cpy,cpz,overlap,refR1,refR2,kn,ks,cn,cs,kr,ktw,'
            'fn,fs,tan_phi,sliding,moment_bending,moment_twist\n')
    for r in rows:
        f.write('%s,%d,%s,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,'
                '%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g\n'
                % ((r[0], r[1], r[2], r[3]) + tuple(r[4]) + tuple(r[5]) + r[6:]))
print('exported %d spheres, %d facets, %d interactions (%d sliding)'
      % (len(sphere_ids), len(facet_ids), len(rows), n_sliding))

pwave = PWaveTimeStep()
gsts = GlobalStiffnessTimeStepper(timestepSafetyCoefficient=1.0, timeStepUpdateInterval=1,
                                  maxDt=1.0, previousDt=1.0, defaultDt=1e-12, active=True)
O.engines = [gsts] + O.engines
O.dt = 1e-12
O.step()
gsts_dt = O.dt
O.loadTmp('settled')     # restores the saved engines (without the time stepper) as well
print('PWaveTimeStep %.6e  GlobalStiffnessTimeStepper raw %.6e' % (pwave, gsts_dt))
summary = {
    'scene': SCENE, 'yade_version': '2023.02a',
    'n_spheres': len(sphere_ids), 'n_facets': len(facet_ids), 'n_interactions': len(rows),
    'n_wall_interactions': sum(1 for r in rows if r[0] == 'w' or r[2] == 'w'),
    'n_sliding_at_export': n_sliding,
    'radii': RADII, 'density': DENSITY, 'box': BOX, 'gravity': GRAVITY, 'friction_angle': FRICTION,
    'settle_damping': SETTLE_DAMPING, 'quench_rounds': QUENCH, 'noslip_at_freeze': NOSLIP, 'settle_dt': settle_dt, 'settle_steps': O.iter,
    'unbalanced_force_at_save': unb,
    'PWaveTimeStep': pwave, 'GlobalStiffnessTimeStepper_raw': gsts_dt,
}
if SCENE == 'viscel':
    summary.update({'tc': TC, 'en': EN, 'et': ET})
else:
    summary.update({'young': YOUNG, 'poisson': POISSON, 'alphaKr': ALPHA_KR, 'alphaKtw': ALPHA_KTW,
                    'always_use_moment_law': True, 'useIncrementalForm': False})
with open(os.path.join(OUT, 'summary.json'), 'w') as f:
    json.dump(summary, f, indent=1)
if BUILD_ONLY:
    sys.exit(0)

# ---------------------------------------------------------------- measurement
newton.damping = 0.0
rng = random.Random(12345)
vel0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * V0 for _ in sphere_ids]
ang0 = [Vector3(rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)) * (V0 / O.bodies[bid].shape.radius)
        for bid in sphere_ids]
# physical time of every trial: NSTEPS steps at the first guess of the limit, so
# at least that many at every candidate near it
NSTEPS = 2000 if QUICK else 20000
GROWTH = 100.0
DT_GUESS = gsts_dt
T_RUN = NSTEPS * DT_GUESS
trials = []

def perturbed(dt):
    O.loadTmp('settled')
    newton.damping = 0.0
    for k, bid in enumerate(sphere_ids):
        O.bodies[bid].state.vel = vel0[k]
        O.bodies[bid].state.angVel = ang0[k]
    O.dt = dt

def kinetic_each():
    out = []
    for bid in sphere_ids:
        st = O.bodies[bid].state
        w = st.angVel
        out.append(0.5 * st.mass * st.vel.squaredNorm()
                   + 0.5 * (st.inertia[0] * w[0] ** 2 + st.inertia[1] * w[1] ** 2 + st.inertia[2] * w[2] ** 2))
    return out

def run(dt, threshold=None, ref_each=None):
    """Runs T_RUN from the perturbed settled state; returns (KE at the end, max KE,
    steps, aborted, KE0, per-sphere max KE, largest per-sphere ratio to ref_each).
    Aborts once KE exceeds threshold, or (ref_each given) once some sphere's KE
    exceeds GROWTH_PP times its ref_each (the trial is then unstable)."""
    perturbed(dt)
    nsteps = int(math.ceil(T_RUN / dt))
    e0 = kinetic()
    each_max = kinetic_each()
    emax, steps, aborted, rmax = e0, 0, False, 0.0
    while steps < nsteps:
        chunk = min(nsteps - steps, 10 if steps < 200 else 100)
        O.run(chunk, True)
        steps += chunk
        e = kinetic()
        if not (e == e):
            e = float('inf')
        emax = max(emax, e)
        if PER_PARTICLE:
            each = kinetic_each()
            each_max = [max(a, b) if b == b else float('inf') for a, b in zip(each_max, each)]
            if ref_each is not None:
                rmax = max(rmax, max(b / a for a, b in zip(ref_each, each)) if e < float('inf') else float('inf'))
                if not (rmax < GROWTH_PP):
                    aborted = True
                    break
        if threshold is not None and not (e < threshold):
            aborted = True
            break
    return e, emax, steps, aborted, e0, each_max, rmax

# reference run at a small step (a quarter of the first guess)
DT_SMALL = 0.25 * DT_GUESS
ke_small_end, ke_small_max, small_steps, _, KE0, small_each_max, _ = run(DT_SMALL)
REF = max(ke_small_end, KE0)
THRESH = GROWTH * REF
if PER_PARTICLE:
    THRESH = float('inf')        # the per-sphere test decides
    GROWTH = GROWTH_PP
print('reference run: dt %.4e, %d steps, KE0 %.4e J, KE end %.4e J, max %.4e J; threshold %.4e J'
      % (DT_SMALL, small_steps, KE0, ke_small_end, ke_small_max, THRESH))

def trial(dt):
    e, emax, steps, aborted, e0, _, rmax = run(dt, THRESH, small_each_max if PER_PARTICLE else None)
    unstable = aborted or not (e < THRESH)
    trials.append({'dt': dt, 'unstable': unstable, 'steps': steps, 'ke_end': e, 'ke_max': emax,
                   'ke_end_over_ref': (rmax if PER_PARTICLE else e / REF)})
    print('  dt=%.8e  %s  steps=%d  KE_end/ref=%.3e  KE_max/ref=%.3e  max per-sphere ratio %.3e'
          % (dt, 'UNSTABLE' if unstable else 'stable', steps, e / REF, emax / REF, rmax))
    sys.stdout.flush()
    return unstable

RTOL = 2e-3 if QUICK else 5e-4
lo, hi = search.bisect(trial, DT_GUESS, 1.05, RTOL, max_trials=60)

summary.update({
    'measurement_damping': 0.0,
    'perturbation_rms_velocity': V0, 'perturbation_rms_angvel': 'V0 / radius', 'seed': 12345,
    'run_time_s': T_RUN, 'steps_at_first_guess': NSTEPS, 'dt_first_guess': DT_GUESS,
    'dt_small': DT_SMALL, 'ke0': KE0, 'ke_small_end': ke_small_end, 'ke_small_max': ke_small_max,
    'growth_factor': GROWTH, 'threshold': THRESH,
    'criterion': ('unstable if some sphere\'s KE > %g x its largest KE in the small-step run (at least its '
                  'initial KE) at any check within T = %.6e s' % (GROWTH_PP, T_RUN)) if PER_PARTICLE else
                 ('unstable if KE > %g x max(KE0, KE_small(T)) at any check or at T = %.6e s' % (GROWTH, T_RUN)),
    'measured_dt_lo': lo, 'measured_dt_hi': hi,
    'wall_time_s': time.time() - t0,
})
with open(os.path.join(OUT, 'summary_%s.json' % TAG), 'w') as f:
    json.dump(summary, f, indent=1)
with open(os.path.join(OUT, 'trials_%s.csv' % TAG), 'w') as f:
    f.write('dt,unstable,steps,ke_end,ke_max,ke_end_over_ref\n')
    for t in trials:
        f.write('%.10e,%d,%d,%.6e,%.6e,%.6e\n' % (t['dt'], t['unstable'], t['steps'], t['ke_end'],
                                                 t['ke_max'], t['ke_end_over_ref']))
# measured.csv: one row per test amplitude (a rerun replaces its own row)
mpath = os.path.join(OUT, 'measured.csv')
header = 'scene,v0,criterion,dt_stable,dt_unstable,criterion_growth,run_time_s,dt_small,newton_damping\n'
CRIT = 'per_sphere' if PER_PARTICLE else 'total'
keep = []
if os.path.exists(mpath):
    with open(mpath) as f:
        keep = [ln for ln in f.readlines()[1:] if ln.split(',')[1:3] != ['%.3e' % V0, CRIT]]
keep.append('%s,%.3e,%s,%.10e,%.10e,%g,%.6e,%.6e,0\n' % (os.path.basename(OUT), V0, CRIT, lo, hi, GROWTH, T_RUN, DT_SMALL))
with open(mpath, 'w') as f:
    f.write(header)
    f.writelines(sorted(keep))
print(json.dumps(summary, indent=1))
