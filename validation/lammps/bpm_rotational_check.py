#!/usr/bin/env python3
"""Check demstep's reading of LAMMPS' `bond_style bpm/rotational`
(src/demstep/material/demstep_bonds.f90): that, linearised about its rest state,
the bond is the interaction kernel's springs (normal K_r, shear K_s at the
bond's middle - lever arms r0/2 from both centres -, bending K_b, twisting K_t)
and its dashpots are (gamma_n, gamma_s, gamma_r r0/2, gamma_t/2).

LAMMPS is not installed here: this script restates, in numpy, the force and
torque formulas of src/BPM/bond_bpm_rotational.cpp (elastic_forces: Wang 2009,
Wang and Mora 2009; damping_forces: Wang et al. 2015; compute: which particle
gets which force and torque), differentiates them at rest by central
differences and compares the 12 x 12 tangent with the kernel's block, written
out here from its definition (demstep_interaction's contact_product:
K = k_n b_n b_n^T + k_t B_t^T B_t + bending and twisting on the relative
rotation), for random bond directions and lengths.

    python3 validation/lammps/bpm_rotational_check.py

Prints the largest relative differences; writes bpm_rotational_check.txt."""
import os
import numpy as np

rng = np.random.default_rng(4)


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def qconj(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def qrot(q, v):
    return qmul(qmul(q, np.concatenate([[0.0], v])), qconj(q))[1:]


def qexp(theta):
    """The unit quaternion of the rotation vector theta."""
    a = np.linalg.norm(theta)
    if a == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return np.concatenate([[np.cos(a / 2)], np.sin(a / 2) * theta / a])


def elastic(x1, x2, q1, q2, r0, kr, ks, kt, kb):
    """force1on2, torque1on2, torque2on1 of elastic_forces (normalize no)."""
    r = x1 - x2
    rm = np.linalg.norm(r)
    r0m = np.linalg.norm(r0)
    q2inv = qconj(q2)
    rb = qrot(q2inv, r)
    f_rot = kr * (rm - r0m) * rb / rm
    gamma = np.arccos(np.clip(rb @ r0 / (rm * r0m), -1, 1))
    s = np.cross(rb, np.cross(rb, r0))
    t = np.cross(r0, rb)
    fs = np.zeros(3)
    ts = np.zeros(3)
    if np.linalg.norm(s) > 0:
        fs = ks * rm * gamma * s / np.linalg.norm(s)
        ts = 0.5 * rm * ks * rm * gamma * t / np.linalg.norm(t)
    mq = np.zeros(4)
    mq[0] = np.sqrt(2) / 2 * np.sqrt(max(rm + rb[2], 0.0) / rm)
    rxy = np.hypot(rb[0], rb[1])
    if rxy != 0:
        m1 = -np.sqrt(2) / 2 / rxy * np.sqrt(max(rm - rb[2], 0.0) / rm)
        mq[1] = m1 * rb[1]
        mq[2] = -m1 * rb[0]
    q21 = qmul(qmul(qconj(mq), qmul(q2inv, q1)), mq)
    tmp = np.hypot(q21[0], q21[3])
    psi = 2 * np.arccos(np.clip(q21[0] / tmp, -1, 1)) if tmp != 0 else 0.0
    if q21[3] < 0:
        psi = -psi
    if q21[3] == 0:
        psi = 0.0
    theta = np.arccos(np.clip(q21[0] ** 2 - q21[1] ** 2 - q21[2] ** 2 + q21[3] ** 2, -1, 1))
    mag_out = q21[0] ** 2 + q21[3] ** 2
    mag_in = q21[1] ** 2 + q21[2] ** 2
    if mag_in == 0:
        cphi = sphi = 0.0
    elif mag_out == 0:
        cphi = q21[2] / np.sqrt(mag_in)
        sphi = -q21[1] / np.sqrt(mag_in)
    else:
        cphi = (q21[1] * q21[3] + q21[0] * q21[2]) / np.sqrt(mag_out * mag_in)
        sphi = (q21[2] * q21[3] - q21[0] * q21[1]) / np.sqrt(mag_out * mag_in)
    tbp = np.array([-kb * theta * sphi, kb * theta * cphi, 0.0])
    ttp = np.array([0.0, 0.0, kt * psi])
    fsp = np.array([-0.5 * ks * rm * theta * cphi, -0.5 * ks * rm * theta * sphi, 0.0])
    tsp = np.array([0.25 * ks * rm ** 2 * theta * sphi, -0.25 * ks * rm ** 2 * theta * cphi, 0.0])
    fs = fs + qrot(mq, fsp)
    ts = ts + qrot(mq, tsp)
    tb = qrot(mq, tbp)
    tt = qrot(mq, ttp)
    f12 = qrot(q2, f_rot + fs)
    t12 = qrot(q2, ts + tt + tb)
    t21 = qrot(q2, ts - tt - tb)
    return f12, t12, t21


def damping(x1, x2, v1, v2, w1, w2, gn, gs, gr, gt):
    """force1on2, torque1on2, torque2on1 of damping_forces alone."""
    r = x1 - x2
    rhat = r / np.linalg.norm(r)
    vn1, vn2 = (v1 @ rhat) * rhat, (v2 @ rhat) * rhat
    f12 = gn * (vn1 - vn2)
    vt1, vt2 = v1 - vn1, v2 - vn2
    half = 0.5 * (vt2 - vt1)
    s1 = -0.5 * np.cross(w1, r) - half
    s2 = 0.5 * np.cross(w2, r) + half
    slide = gs * (s1 - s2)
    f12 = f12 + slide
    td = 0.5 * np.cross(r, slide)
    t12 = td.copy()
    t21 = td.copy()
    vroll = np.cross(w1, rhat) - np.cross(w2, rhat)
    td = 0.5 * gr * np.cross(r, vroll)
    t12 = t12 + td
    t21 = t21 - td
    td = 0.5 * gt * ((w1 @ rhat) * rhat - (w2 @ rhat) * rhat)
    t12 = t12 + td
    t21 = t21 - td
    return f12, t12, t21


def generalised(f12, t12, t21):
    """(f1, t1, f2, t2) as compute() applies them: f[i1] -= f12, torque[i1] += t21, ..."""
    return np.concatenate([-f12, t21, f12, t12])


def kernel_block(n, k, arm_i, arm_j):
    """The kernel's 12 x 12 block on (u_i, theta_i, u_j, theta_j), n from i to j."""
    nn = np.outer(n, n)
    p = np.eye(3) - nn
    nx = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    bn = np.concatenate([-n, np.zeros(3), n, np.zeros(3)])
    bt = np.hstack([-p, arm_i * nx, p, arm_j * nx])
    br = np.hstack([np.zeros((3, 3)), -np.eye(3), np.zeros((3, 3)), np.eye(3)])
    rot = k[2] * p + k[3] * nn
    return k[0] * np.outer(bn, bn) + k[1] * bt.T @ bt + br.T @ rot @ br


lines = []
worst_k = worst_c = 0.0
for trial in range(8):
    d = rng.normal(size=3)
    d /= np.linalg.norm(d)
    r0m = rng.uniform(1.5, 2.5)
    x1 = rng.normal(size=3)
    x2 = x1 - r0m * d                      # r0 = x1 - x2 at rest, unit quaternions
    r0 = x1 - x2
    kr, ks, kt, kb = rng.uniform(0.5, 2.0, size=4) * [1e3, 4e2, 50, 80]
    gn, gs, gr, gt = rng.uniform(0.5, 2.0, size=4) * [3, 2, 1, 0.5]
    one = np.array([1.0, 0.0, 0.0, 0.0])
    # h: the angles come from acos near 1, whose rounding is about 1e-16/angle,
    # so a small h loses digits (1e-5: 7e-6 relative) and a large one the
    # O(h^2) terms (1e-3: 2e-7); 1e-4 gives 6e-8
    h = 1e-4
    jk = np.zeros((12, 12))
    jc = np.zeros((12, 12))
    for c in range(12):
        gp = []
        for sgn in (1.0, -1.0):
            q = np.zeros(12)
            q[c] = sgn * h
            # displacement (u1, th1, u2, th2): positions and orientations
            f = elastic(x1 + q[0:3], x2 + q[6:9], qexp(q[3:6]), qexp(q[9:12]), r0, kr, ks, kt, kb)
            g = damping(x1, x2, q[0:3], q[6:9], q[3:6], q[9:12], gn, gs, gr, gt)
            gp.append((generalised(*f), generalised(*g)))
        jk[:, c] = -(gp[0][0] - gp[1][0]) / (2 * h)
        jc[:, c] = -(gp[0][1] - gp[1][1]) / (2 * h)
    n = (x2 - x1) / r0m                    # from i = particle 1 to j = particle 2
    kk = kernel_block(n, [kr, ks, kb, kt], 0.5 * r0m, 0.5 * r0m)
    kc = kernel_block(n, [gn, gs, 0.5 * gr * r0m, 0.5 * gt], 0.5 * r0m, 0.5 * r0m)
    ek = np.abs(jk - kk).max() / np.abs(kk).max()
    ec = np.abs(jc - kc).max() / np.abs(kc).max()
    worst_k, worst_c = max(worst_k, ek), max(worst_c, ec)
    lines.append("trial %d: r0 %.3f, |tangent - kernel|/|kernel| = %.2e (stiffness), %.2e (dashpots)"
                 % (trial, r0m, ek, ec))
lines.append("largest: %.2e (stiffness, central differences h = 1e-4), %.2e (dashpots, linear: exact)"
             % (worst_k, worst_c))
text = "\n".join(lines) + "\n"
print(text, end="")
open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "bpm_rotational_check.txt"), "w").write(text)
