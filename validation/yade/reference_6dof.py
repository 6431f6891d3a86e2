#!/usr/bin/env python3
"""Independent reference (numpy/scipy only, no demstep code) for the Yade runs.

For each data/CASE (written by yade_stability.py) it reads particles.txt,
contacts.txt and summary.json, assembles the stiffness matrix of the linearised
system Yade integrates (6 degrees of freedom per sphere: translation and
rotation; normal spring k_n along the branch vector, tangential spring k_t in
the plane normal to it, periodic minimum image) and gives dt = 2/omega_max for
several model variants, next to Yade's measured limit and its own estimates.

Usage: python3 reference_6dof.py [CASE ...]      (default: every data/ case)
Writes data/CASE/reference.json and results.md (the table of the README).
"""
import json
import math
import os
import sys

import numpy as np
import scipy.linalg as sla

HERE = os.path.dirname(os.path.abspath(__file__))


def read_case(case):
    d = os.path.join(HERE, 'data', case)
    part = np.loadtxt(os.path.join(d, 'particles.txt'), comments='#', ndmin=2)
    cont = np.loadtxt(os.path.join(d, 'contacts.txt'), comments='#', ndmin=2)
    with open(os.path.join(d, 'cell.json')) as f:
        cell = json.load(f)
    with open(os.path.join(d, 'summary.json')) as f:
        summ = json.load(f)
    return part, cont, cell, summ


def skew(n):
    return np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])


def contact_geometry(part, cont, cell):
    """Branch vectors through the nearest periodic image."""
    lo = np.array(cell['cell_lo'])
    L = np.array(cell['cell_hi']) - lo
    x = part[:, 0:3]
    i = cont[:, 0].astype(int) - 1
    j = cont[:, 1].astype(int) - 1
    d = x[j] - x[i]
    d -= L * np.round(d / L)
    l = np.linalg.norm(d, axis=1)
    n = d / l[:, None]
    r = part[:, 7]
    delta = r[i] + r[j] - l
    return i, j, n, l, delta


def assemble(part, cont, cell, rotations=True, tangential=True, arms='radius',
             alpha=False, prestress=False):
    """Stiffness K (f = -K q) of the linearised Yade system.

    arms: lever arms of the tangential force, 'radius' (r_i) or 'contact'
          (r_i - delta/2, Yade's ScGeom contact point, used for the torques in a
          periodic cell by Law2_ScGeom_FrictPhys_CundallStrack).
    alpha: Yade's avoidGranularRatcheting kinematics (default on in
          Ig2_Sphere_Sphere_ScGeom): shear increment from
          alpha (v_j - v_i) + r_j n x w_j + r_i n x w_i, alpha = (r_i + r_j)/l,
          with the radii (not the contact point) as kinematic arms. With
          alpha=True the tangential block is k_t B_f^T B_k, not symmetric.
    prestress: geometric stiffness of the compressed normal springs,
          -(F_n/l)(I - n n^T) on the relative translation (F_n = k_n delta).
    """
    npart = part.shape[0]
    ndof = 6 if rotations else 3
    K = np.zeros((ndof * npart, ndof * npart))
    i_, j_, n_, l_, d_ = contact_geometry(part, cont, cell)
    r = part[:, 7]
    for c in range(cont.shape[0]):
        i, j, n, l, delta = i_[c], j_[c], n_[c], l_[c], d_[c]
        kn, kt = cont[c, 2], cont[c, 3]
        P = np.eye(3) - np.outer(n, n)
        Kn = kn * np.outer(n, n)
        if prestress:
            Kn = Kn - (kn * delta / l) * P
        ii = slice(ndof * i, ndof * i + 3)
        jj = slice(ndof * j, ndof * j + 3)
        K[ii, ii] += Kn
        K[jj, jj] += Kn
        K[ii, jj] -= Kn
        K[jj, ii] -= Kn
        if not tangential or kt == 0.0:
            continue
        a = (r[i] + r[j]) / l if alpha else 1.0
        if rotations:
            N = skew(n)
            if arms == 'radius':
                ai, aj = r[i], r[j]
            else:
                ai, aj = r[i] - 0.5 * delta, r[j] - 0.5 * delta
            ki, kj = (r[i], r[j]) if alpha else (ai, aj)   # kinematic arms
            Bk = np.hstack([-a * P, ki * N, a * P, kj * N])
            Bf = np.hstack([-P, ai * N, P, aj * N])
            idx = np.r_[6 * i:6 * i + 6, 6 * j:6 * j + 6]
        else:
            Bk = np.hstack([-a * P, a * P])
            Bf = np.hstack([-P, P])
            idx = np.r_[3 * i:3 * i + 3, 3 * j:3 * j + 3]
        K[np.ix_(idx, idx)] += kt * (Bf.T @ Bk)
    return K


def mass_vector(part, rotations=True):
    m = part[:, 6]
    inertia = part[:, 9]
    if rotations:
        return np.column_stack([m, m, m, inertia, inertia, inertia]).ravel()
    return np.column_stack([m, m, m]).ravel()


def omega2_max(K, mv, symmetric):
    s = 1.0 / np.sqrt(mv)
    A = K * s[:, None] * s[None, :]
    if symmetric:
        A = 0.5 * (A + A.T)
        lam = sla.eigvalsh(A)
        return lam[-1], 0.0, A
    lam = sla.eigvals(A)
    k = np.argmax(lam.real)
    return lam[k].real, float(np.max(np.abs(lam.imag))), A


def dt_of(w2):
    return 2.0 / math.sqrt(w2)


def gsts_replica(part, cont, cell, factor):
    """GlobalStiffnessTimeStepper::computeStiffnesses + findTimeStepFromBody."""
    i_, j_, n_, l_, d_ = contact_geometry(part, cont, cell)
    npart = part.shape[0]
    Kt = np.zeros((npart, 3))
    Kr = np.zeros((npart, 3))
    r = part[:, 7]
    for c in range(cont.shape[0]):
        n = n_[c]
        kn, ks = cont[c, 2], cont[c, 3]
        diag = n ** 2 * (kn - ks) + ks
        rdiag = ks * np.array([n[1] ** 2 + n[2] ** 2, n[0] ** 2 + n[2] ** 2, n[0] ** 2 + n[1] ** 2])
        for b in (i_[c], j_[c]):
            Kt[b] += diag
            Kr[b] += rdiag * r[b] ** 2
    dt2 = np.inf
    for b in range(npart):
        if not Kt[b].any():
            continue
        t2 = part[b, 6] / Kt[b].max()
        with np.errstate(divide='ignore'):
            r2 = np.min(np.where(Kr[b] > 0, part[b, 9] / np.where(Kr[b] > 0, Kr[b], 1.0), np.inf))
        dt2 = min(dt2, t2, r2)
    return factor * math.sqrt(dt2)


def analyse(case):
    part, cont, cell, summ = read_case(case)
    res = {'case': case, 'n_particles': int(part.shape[0]), 'n_contacts': int(cont.shape[0])}
    variants = {
        # what Yade integrates, linearised about the frozen state
        'yade_exact': dict(rotations=True, tangential=True, arms='contact', alpha=True, prestress=True),
        'yade_exact_no_prestress': dict(rotations=True, tangential=True, arms='contact', alpha=True, prestress=False),
        # symmetric 6-DOF models from the contact list alone (i j k_n k_t + radii)
        'sym6_radius_arms': dict(rotations=True, tangential=True, arms='radius'),
        'sym6_contact_point_arms': dict(rotations=True, tangential=True, arms='contact'),
        'sym6_radius_arms_prestress': dict(rotations=True, tangential=True, arms='radius', prestress=True),
        # reduced models
        'trans_normal_tangential': dict(rotations=False, tangential=True),
        'trans_normal_only': dict(rotations=False, tangential=False),
    }
    for name, kw in variants.items():
        K = assemble(part, cont, cell, **kw)
        mv = mass_vector(part, kw['rotations'])
        sym = not kw.get('alpha', False)
        w2, imag, A = omega2_max(K, mv, symmetric=sym)
        res[name] = {'omega2_max': w2, 'dt': dt_of(w2), 'max_abs_imag': imag}
        if name == 'sym6_contact_point_arms':
            # (demstep's model: lever arms to the contact point, r - delta/2)
            # Gershgorin: largest absolute row sum of the mass-scaled matrix
            B = np.abs(A)
            g = np.max(np.sum(B, axis=1))
            res['gershgorin_sym6'] = {'omega2_bound': g, 'dt': dt_of(g)}
            # Collatz-Wielandt: lambda_max(A) <= rho(|A|) <= max (|A| v)_i / v_i
            # for any v > 0; v = 1 (Gershgorin), then two steps v <- |A| v
            # (floored at 1e-3 of the largest entry), the smallest quotient
            v = np.ones(B.shape[0])
            cw = np.inf
            for _ in range(3):
                r = B @ v
                cw = min(cw, np.max(r / v))
                v = np.maximum(r / np.max(r), 1e-3)
            res['collatz_sym6'] = {'omega2_bound': cw, 'dt': dt_of(cw)}
            asym = np.max(np.abs(K - K.T)) / np.max(np.abs(K))
            res['sym6_contact_point_arms']['K_asymmetry'] = asym
    res['gsts_replica_1.41044'] = gsts_replica(part, cont, cell, 1.41044)
    res['gsts_replica_sqrt2'] = gsts_replica(part, cont, cell, math.sqrt(2.0))
    rho, E = summ['density'], summ['young']
    res['pwave_replica'] = float(np.min(part[:, 7]) / math.sqrt(E / rho))
    res['yade'] = {k: summ[k] for k in ('measured_dt_lo', 'measured_dt_hi', 'GlobalStiffnessTimeStepper_raw',
                                        'PWaveTimeStep')}
    with open(os.path.join(HERE, 'data', case, 'reference.json'), 'w') as f:
        json.dump(res, f, indent=1)
    return res, summ


def table(rows):
    out = []
    out.append('| assembly | particles | contacts | Yade measured limit [lo, hi] (s) | 6-DOF as Yade integrates | 6-DOF symmetric (radius arms) | translational, normal only | translational, normal + tangential | Gershgorin (6-DOF) | GlobalStiffnessTimeStepper (raw) | PWaveTimeStep |')
    out.append('|---|---|---|---|---|---|---|---|---|---|---|')
    for res, summ in rows:
        lo, hi = summ['measured_dt_lo'], summ['measured_dt_hi']
        mid = 0.5 * (lo + hi)

        def f(dt):
            return '%.5e (%.4f)' % (dt, dt / mid)
        out.append('| %s | %d | %d | [%.5e, %.5e] | %s | %s | %s | %s | %s | %s | %s |' % (
            res['case'], res['n_particles'], res['n_contacts'], lo, hi,
            f(res['yade_exact']['dt']), f(res['sym6_radius_arms']['dt']),
            f(res['trans_normal_only']['dt']), f(res['trans_normal_tangential']['dt']),
            f(res['gershgorin_sym6']['dt']),
            f(summ['GlobalStiffnessTimeStepper_raw']), f(summ['PWaveTimeStep'])))
    out.append('')
    out.append('In parentheses: the ratio to the midpoint of the measured bracket.')
    out.append('')
    out.append('| assembly | 6-DOF as Yade, no prestress | 6-DOF sym., contact-point arms | 6-DOF sym., radius arms + prestress | GSTS replica (1.41044) | GSTS replica (sqrt 2) | max imag. part (Yade-exact) |')
    out.append('|---|---|---|---|---|---|---|')
    for res, summ in rows:
        mid = 0.5 * (summ['measured_dt_lo'] + summ['measured_dt_hi'])

        def f(dt):
            return '%.5e (%.4f)' % (dt, dt / mid)
        out.append('| %s | %s | %s | %s | %s | %s | %.2e |' % (
            res['case'], f(res['yade_exact_no_prestress']['dt']), f(res['sym6_contact_point_arms']['dt']),
            f(res['sym6_radius_arms_prestress']['dt']), f(res['gsts_replica_1.41044']),
            f(res['gsts_replica_sqrt2']), res['yade_exact']['max_abs_imag']))
    return '\n'.join(out) + '\n'


def main():
    cases = sys.argv[1:] or [c for c in ('sc', 'fcc', 'random')
                             if os.path.exists(os.path.join(HERE, 'data', c, 'summary.json'))]
    rows = []
    for c in cases:
        res, summ = analyse(c)
        rows.append((res, summ))
        print('%s: measured [%.6e, %.6e]  yade-exact 6-DOF %.6e  sym 6-DOF %.6e  trans-normal %.6e'
              % (c, summ['measured_dt_lo'], summ['measured_dt_hi'], res['yade_exact']['dt'],
                 res['sym6_radius_arms']['dt'], res['trans_normal_only']['dt']))
        sys.stdout.flush()
    with open(os.path.join(HERE, 'results.md'), 'w') as f:
        f.write(table(rows))
    print(table(rows))


if __name__ == '__main__':
    main()
