#!/usr/bin/env python3
"""Independent reference for the damped Yade scenes (plain numpy/scipy, no demstep code).

Reads data/SCENE/{particles.csv,interactions.csv,summary.json,measured.csv} written
by yade_damped.py, builds the linearised 6-dof stiffness K and dashpot matrix C of
what Yade 2023.02a integrates (CONVENTIONS_DAMPING.md gives every formula with its
source line), and computes

  undamped limit  h0 = 2 / sqrt(lambda_max(A)),              A = M^-1/2 K M^-1/2
  damped limit    h* = smallest h with lambda_max(h^2 A + 2 h B) = 4,  B = M^-1/2 C M^-1/2

(bisection on h, then Newton on the top eigenvalue; dense scipy.linalg.eigh).
With --map, h* is also checked against the spectral radius of the dense one-step
map of the leapfrog scheme with the dashpot on the lagged half-step velocity,
  v' = v - h M^-1 (K x + C v),  x' = x + h v',
just below and just above h*.

Facets are ground (fixed): their rows and columns are dropped.
Writes data/SCENE/reference.json and results_damped.md.

Usage: /usr/bin/python3 reference_damped.py [--map] [SCENE ...]
"""
import csv
import json
import math
import os
import sys

import numpy as np
import scipy.linalg as sla

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = ('viscel', 'cohfrict', 'viscel_creeping', 'viscel_noslip')


def skew(a):
    """[a]x, so that skew(a) @ b = a x b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def read_csv(path):
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith('#')]
    return list(csv.DictReader(lines))


def load(scene):
    d = os.path.join(HERE, 'data', scene)
    parts = read_csv(os.path.join(d, 'particles.csv'))
    inter = read_csv(os.path.join(d, 'interactions.csv'))
    with open(os.path.join(d, 'summary.json')) as f:
        summary = json.load(f)
    meas = []
    mpath = os.path.join(d, 'measured.csv')
    if os.path.exists(mpath):
        meas = read_csv(mpath)
    return parts, inter, summary, meas


def check_parameters(scene, parts, inter, summary):
    """Largest relative difference between each exported per-contact coefficient and
    the Ip2 formula of CONVENTIONS_DAMPING.md evaluated from masses, radii and the
    material constants (a check that the conventions are read right)."""
    mass = np.array([float(p['mass']) for p in parts])
    worst = {}

    def note(name, got, want):
        err = abs(got - want) / max(abs(want), 1e-300)
        worst[name] = max(worst.get(name, 0.0), err)

    for c in inter:
        if scene == 'viscel':
            m2 = mass[int(c['i2'])]
            m1 = m2 if c['kind1'] == 'w' else mass[int(c['i1'])]   # a facet has mass 0: Yade uses the sphere's
            mr = m1 * m2 / (m1 + m2)
            tc, en, et = summary['tc'], summary['en'], summary['et']
            note('kn', float(c['kn']), (math.pi ** 2 + math.log(en) ** 2) / tc ** 2 * mr)
            note('cn', float(c['cn']), -2.0 * math.log(en) / tc * mr)
            note('ks', float(c['ks']), 2.0 / 7.0 * (math.pi ** 2 + math.log(et) ** 2) / tc ** 2 * mr)
            note('cs', float(c['cs']), -4.0 / 7.0 * math.log(et) / tc * mr)
        else:
            e, nu = summary['young'], summary['poisson']
            da, db = float(c['refR1']), float(c['refR2'])
            kn = 2.0 * e * da * e * db / (e * da + e * db)
            ks = 2.0 * e * da * nu * e * db * nu / (e * da * nu + e * db * nu)
            note('kn', float(c['kn']), kn)
            note('ks', float(c['ks']), ks)
            note('kr', float(c['kr']), da * db * ks * summary['alphaKr'])
            note('ktw', float(c['ktw']), da * db * ks * summary['alphaKtw'])
    return worst


def assemble(scene, parts, inter, variant, slip_fraction=None):
    """K, C (6n x 6n) and the mass vector. variant:
    'yade'      what Yade integrates: ViscEl contact-point arms for springs and
                dashpots; CohFrict sphere-sphere shear with Yade's alpha and radius
                arms on the kinematic side, contact-point arms on the force side
                (non-symmetric), facet-sphere contact-point arms on both sides;
    'symmetric' every contact with contact-point arms on both sides, no alpha.
    slip_fraction: if given, contacts whose elastic shear force is at least this
    fraction of tan(phi) F_n are taken as sliding (no tangential spring or dashpot,
    as Yade's laws do at the Coulomb limit)."""
    n = len(parts)
    x = np.array([[float(p['x']), float(p['y']), float(p['z'])] for p in parts])
    mass = np.array([float(p['mass']) for p in parts])
    inertia = np.array([float(p['inertia']) for p in parts])
    fixed = np.array([int(p['fixed']) for p in parts], dtype=bool)
    K = np.zeros((6 * n, 6 * n))
    C = np.zeros((6 * n, 6 * n))
    eye = np.eye(3)
    for c in inter:
        nv = np.array([float(c['nx']), float(c['ny']), float(c['nz'])])
        nv /= np.linalg.norm(nv)
        cp = np.array([float(c['cpx']), float(c['cpy']), float(c['cpz'])])
        P = eye - np.outer(nv, nv)
        N = skew(nv)
        body1 = None if c['kind1'] == 'w' else int(c['i1'])
        body2 = None if c['kind2'] == 'w' else int(c['i2'])
        # columns of the 12 generalized coordinates (u1, th1, u2, th2) -> global dofs
        idx = []
        for b in (body1, body2):
            idx.append(None if b is None else list(range(6 * b, 6 * b + 6)))
        c1 = cp - x[body1] if body1 is not None else np.zeros(3)
        c2 = cp - x[body2] if body2 is not None else np.zeros(3)
        # u_rel = (u1 + th1 x c1) - (u2 + th2 x c2): the velocity Yade's ViscEl law
        # uses; force on body 2 = S u_rel, on body 1 = -S u_rel, torques c2 x f, -c1 x f
        Bf = np.hstack([eye, -skew(c1), -eye, skew(c2)])
        Bn = np.outer(nv, nv) @ Bf
        Bfs = P @ Bf
        kn, ks = float(c['kn']), float(c['ks'])
        cn, cs = float(c['cn']), float(c['cs'])
        if slip_fraction is not None and float(c['fs']) >= slip_fraction * float(c['tan_phi']) * float(c['fn']):
            ks, cs = 0.0, 0.0
        kr, ktw = float(c['kr']), float(c['ktw'])
        Kc = kn * Bn.T @ Bn
        if scene == 'cohfrict' and variant == 'yade' and c['kind1'] == 'p' and c['kind2'] == 'p':
            # Ig2_Sphere_Sphere_ScGeom(6D) avoidGranularRatcheting: shear increment
            # P[alpha (u2 - u1) + r2 n x th2 + r1 n x th1]; the law subtracts ks times it
            # from the shear force on body 2, i.e. the displacement of 1 relative to 2 is
            # P[alpha (u1 - u2) - r1 n x th1 - r2 n x th2]
            r1, r2, ov = float(c['refR1']), float(c['refR2']), float(c['overlap'])
            alpha = (r1 + r2) / (r1 + r2 - ov)
            Bk = np.hstack([alpha * P, -r1 * N, -alpha * P, -r2 * N])
            Kc += ks * Bfs.T @ Bk
        else:
            Kc += ks * Bfs.T @ Bfs
        # rolling and twisting springs on the relative rotation th1 - th2
        if kr != 0.0 or ktw != 0.0:
            R = np.hstack([np.zeros((3, 3)), eye, np.zeros((3, 3)), -eye])
            Kc += R.T @ (kr * P + ktw * np.outer(nv, nv)) @ R
        Cc = cn * Bn.T @ Bn + cs * Bfs.T @ Bfs
        for a in range(2):
            if idx[a] is None:
                continue
            for b in range(2):
                if idx[b] is None:
                    continue
                K[np.ix_(idx[a], idx[b])] += Kc[6 * a:6 * a + 6, 6 * b:6 * b + 6]
                C[np.ix_(idx[a], idx[b])] += Cc[6 * a:6 * a + 6, 6 * b:6 * b + 6]
    mdiag = np.stack([mass, mass, mass, inertia, inertia, inertia], axis=1).reshape(-1)
    free = np.repeat(~fixed, 6)
    return K[np.ix_(free, free)], C[np.ix_(free, free)], mdiag[free]


def lam_max(S):
    w, v = sla.eigh(S, subset_by_index=[S.shape[0] - 1, S.shape[0] - 1])
    return w[0], v[:, 0]


def damped_limit(A, B):
    """Smallest h with lambda_max(h^2 A + 2 h B) = 4 (the function increases with h)."""
    lamA, _ = lam_max(A)
    hi = 2.0 / math.sqrt(lamA)          # at the undamped limit the value is >= 4
    lo = 0.0
    for _ in range(200):                # widen hi in case B = 0 and rounding
        if lam_max(hi * hi * A + 2 * hi * B)[0] >= 4.0:
            break
        hi *= 1.01
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if lam_max(mid * mid * A + 2 * mid * B)[0] >= 4.0:
            hi = mid
        else:
            lo = mid
        if hi - lo < 1e-13 * hi:
            break
    # Newton polish on f(h) = lambda_max(h^2 A + 2hB) - 4, f'(h) = v^T (2hA + 2B) v
    h = 0.5 * (lo + hi)
    for _ in range(5):
        lam, v = lam_max(h * h * A + 2 * h * B)
        d = v @ ((2 * h * A + 2 * B) @ v)
        hn = h - (lam - 4.0) / d
        if not (lo <= hn <= hi):
            break
        if abs(hn - h) < 1e-15 * h:
            h = hn
            break
        h = hn
    return h


def map_radius(A, B, h):
    """Spectral radius of the leapfrog one-step map in mass-scaled coordinates."""
    n = A.shape[0]
    eye = np.eye(n)
    # v' = (I - hB) v - h A x ;  x' = x + h v'
    top = np.hstack([eye - h * h * A, h * (eye - h * B)])
    bot = np.hstack([-h * A, eye - h * B])
    T = np.vstack([top, bot])
    z = sla.eigvals(T)
    # zero-stiffness, undamped directions (free spins) give a defective double
    # eigenvalue 1, which rounding splits by ~1e-8: instability of this scheme
    # is at z = -1, so the radius over Re z < 0 is the one that matters
    return np.max(np.abs(z)), np.max(np.abs(z[z.real < 0]))


def law_of(scene):
    """The contact law of a data directory: ViscElPhys or CohFrictPhys."""
    return 'viscel' if scene.startswith('viscel') else 'cohfrict'


def analyse(scene, do_map):
    parts, inter, summary, meas = load(scene)
    law = law_of(scene)
    out = {'scene': scene, 'n_particles': len(parts), 'n_interactions': len(inter)}
    out['parameter_check_max_rel_error'] = check_parameters(law, parts, inter, summary)
    for variant in (('yade', 'symmetric') if law == 'cohfrict' else ('yade',)):
        K, C, m = assemble(law, parts, inter, variant)
        s = 1.0 / np.sqrt(m)
        Kn = K * s[:, None] * s[None, :]
        B = C * s[:, None] * s[None, :]
        asym = np.max(np.abs(Kn - Kn.T)) / np.max(np.abs(Kn))
        A = 0.5 * (Kn + Kn.T)
        wA = sla.eigvalsh(A)
        wB = sla.eigvalsh(B)
        res = {'K_asymmetry_rel': float(asym), 'A_min_eig': float(wA[0]), 'A_max_eig': float(wA[-1]),
               'B_min_eig': float(wB[0]), 'B_max_eig': float(wB[-1])}
        res['undamped_limit'] = 2.0 / math.sqrt(wA[-1])
        res['undamped_limits_top5_modes'] = [2.0 / math.sqrt(w) for w in wA[::-1][:5]]
        if asym > 1e-12:
            wfull = sla.eigvals(Kn)
            res['undamped_limit_nonsym'] = 2.0 / math.sqrt(np.max(wfull.real))
            res['nonsym_max_imag'] = float(np.max(np.abs(wfull.imag)))
        res['damped_limit'] = damped_limit(A, B)
        if do_map and variant == 'yade':
            h = res['damped_limit']
            res['map_radius_0.999'] = float(map_radius(A, B, 0.999 * h)[1])
            res['map_radius_1.001'] = float(map_radius(A, B, 1.001 * h)[1])
            with open(os.path.join(HERE, 'data', scene, 'map_check.json'), 'w') as f:
                json.dump({'damped_limit': h, 'map_radius_0.999': res['map_radius_0.999'],
                           'map_radius_1.001': res['map_radius_1.001']}, f, indent=1)
        out[variant] = res
        print(scene, variant, json.dumps(res))
        sys.stdout.flush()
    # contacts near the Coulomb limit taken as sliding (explains the larger test amplitude)
    for frac in (0.95,):
        K, C, m = assemble(law, parts, inter, 'yade', slip_fraction=frac)
        sc = 1.0 / np.sqrt(m)
        A = K * sc[:, None] * sc[None, :]
        A = 0.5 * (A + A.T)
        B = C * sc[:, None] * sc[None, :]
        nsl = sum(1 for c in inter if float(c['fs']) >= frac * float(c['tan_phi']) * float(c['fn']))
        out['near_slip_%g' % frac] = {'n_sliding': nsl, 'undamped_limit': 2.0 / math.sqrt(lam_max(A)[0]),
                                      'damped_limit': damped_limit(A, B)}
        print(scene, 'near slip', frac, json.dumps(out['near_slip_%g' % frac]))
    out['measured'] = [{'v0': float(r['v0']), 'criterion': r['criterion'], 'lo': float(r['dt_stable']),
                        'hi': float(r['dt_unstable'])} for r in meas]
    with open(os.path.join(HERE, 'data', scene, 'reference.json'), 'w') as f:
        json.dump(out, f, indent=1)
    return out, summary


def write_results(results):
    lines = ['# Yade damped scenes: measured largest stable step against the linearised model', '',
             'Written by `reference_damped.py` from `data/*/` (see README.md, section',
             '"Damped scenes"). Times in seconds. Ratio = model damped limit / midpoint of',
             'the measured bracket.', '',
             '| scene | V0 (m/s) | criterion | measured [lo, hi] | model undamped | model damped (as Yade) | ratio | '
             'model damped (symmetric, contact-point arms) | ratio | model damped, contacts at >= 0.95 of the Coulomb limit sliding | ratio |',
             '|---|---|---|---|---|---|---|---|---|---|---|']
    for out, summary in results:
        y = out['yade']
        s = out.get('symmetric', y)     # viscel: Yade's law is already symmetric
        ns = out['near_slip_0.95']
        for mrow in out['measured'] or [None]:
            if mrow is not None:
                lo, hi = mrow['lo'], mrow['hi']
                mid = 0.5 * (lo + hi)
                v0, meas = '%.0e | %s' % (mrow['v0'], mrow['criterion']), '[%.5e, %.5e]' % (lo, hi)
                r1, r2 = '%.4f' % (y['damped_limit'] / mid), '%.4f' % (s['damped_limit'] / mid)
                r3 = '%.4f' % (ns['damped_limit'] / mid)
            else:
                v0, meas, r1, r2, r3 = '- | -', 'not measured', '-', '-', '-'
            lines.append('| %s | %s | %s | %.5e | %.5e | %s | %.5e | %s | %.5e (%d sliding) | %s |'
                         % (out['scene'], v0, meas, y['undamped_limit'], y['damped_limit'], r1, s['damped_limit'], r2,
                            ns['damped_limit'], ns['n_sliding'], r3))
    lines += ['', '| scene | spheres | interactions | max rel. error of kn, ks, cn, cs, kr, ktw against the '
              'Ip2 formulas | K asymmetry | map radius at 0.999 h*, 1.001 h* |', '|---|---|---|---|---|---|']
    for out, summary in results:
        pc = ', '.join('%s %.1e' % (k, v) for k, v in sorted(out['parameter_check_max_rel_error'].items()))
        y = out['yade']
        mpath = os.path.join(HERE, 'data', out['scene'], 'map_check.json')
        if os.path.exists(mpath):        # written by a --map run (dense 2n x 2n eigenvalues, slow)
            with open(mpath) as f:
                mc = json.load(f)
            mr = '%.9f, %.9f' % (mc['map_radius_0.999'], mc['map_radius_1.001'])
        else:
            mr = 'not run'
        lines.append('| %s | %d | %d | %s | %.1e | %s |'
                     % (out['scene'], out['n_particles'], out['n_interactions'], pc, y['K_asymmetry_rel'], mr))
    with open(os.path.join(HERE, 'results_damped.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')


def radius_table(scene, dts):
    """Spectral radius of the one-step map of the 'yade' linearisation at given steps,
    (the largest |z| with Re z < 0 and over all z)."""
    parts, inter, summary, meas = load(scene)
    K, C, m = assemble(law_of(scene), parts, inter, 'yade')
    s = 1.0 / np.sqrt(m)
    A = K * s[:, None] * s[None, :]
    A = 0.5 * (A + A.T)
    B = C * s[:, None] * s[None, :]
    rows = []
    for h in dts:
        rho_all, rho = map_radius(A, B, h)
        rows.append({'dt': h, 'rho_re_neg': float(rho), 'rho_all': float(rho_all),
                     'log_rho_per_step': float(math.log(rho))})
        print(scene, 'dt %.6e rho(Re z<0) %.9f ln(rho) per step %.3e  rho(all) %.12f'
              % (h, rho, math.log(rho), rho_all))
        sys.stdout.flush()
    with open(os.path.join(HERE, 'data', scene, 'map_radius.json'), 'w') as f:
        json.dump(rows, f, indent=1)


def main():
    args = sys.argv[1:]
    if args and args[0] == '--radius':
        radius_table(args[1], [float(a) for a in args[2].split(',')])
        return
    do_map = '--map' in args
    scenes = [a for a in args if a in SCENES] or list(SCENES)
    results = []
    for sc in scenes:
        if os.path.exists(os.path.join(HERE, 'data', sc, 'interactions.csv')):
            results.append(analyse(sc, do_map))
    write_results(results)


if __name__ == '__main__':
    main()
