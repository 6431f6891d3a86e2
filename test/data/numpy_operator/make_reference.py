#!/usr/bin/env python3
"""An independent dense numpy assembly of the stability operator of random
clump packings (rigid bodies) and random bonded packings, for test_bodies and
test_bonds ("the operator against a dense numpy assembly").

For each scene it writes SCENE.txt: a header line of counts and parameters,
one line per sphere and, for clumps, its body, for bonds the bonded pairs,
then every eigenvalue omega^2 of K v = omega^2 M v, ascending. The Fortran
tests build the same scene through the library and compare the spectra (1e-10
of the largest). numpy only; run from anywhere:

    python3 test/data/numpy_operator/make_reference.py

What is assembled here, from the scene alone (no demstep code):
- every pair of spheres of different bodies (clumps) closer than r_i + r_j,
  and every sphere below the floor z = floor_z, is a contact of the linear
  law: k_n, k_t, rolling k_r = rolling k_t R*^2, twisting k_w = twisting
  k_t R*^2 (R* = r_i r_j/(r_i + r_j); on the floor R* = r), the shear spring at
  arms r - d/2 from the centres (d the overlap);
- a bond (bonded packings) is the same block with the bond model's own
  stiffnesses and arms: PFC's parallel bond (Potyondy and Cundall 2004:
  k_n = kbar_n A, k_t = kbar_s A, k_r = kbar_n I, k_w = kbar_s J, Rbar =
  lambda min(r_i, r_j), A = pi Rbar^2, I = pi Rbar^4/4, J = pi Rbar^4/2, arms
  r - d/2 with d = r_i + r_j - L) or Yade's CohFrictPhys (kn = 2 E r_i r_j/
  (r_i + r_j), ks = poisson kn, the shear spring alpha ks with alpha =
  (r_i + r_j)/L, kr = r_i r_j ks alpha_kr, ktw = r_i r_j ks alpha_ktw, arms
  r - d/2), normal along x_j - x_i;
- the 12 x 12 block of one spring on (u_i, theta_i, u_j, theta_j):
  k_n b b^T + k_t B^T B + D^T (k_r P + k_w n n^T) D with b = (-n, 0, n, 0),
  B = (-P, a_i [n]x, P, a_j [n]x), D = (0, -I, 0, I), P = I - n n^T;
- a clump's mass is the sum of its members', its tensor the members'
  2/5 m r^2 I plus m (|d|^2 I - d d^T) about the centre of mass (Yade's sum,
  overlaps not removed), each member's motion u + theta x d (the rigid map);
- M^-1/2 K M^-1/2 by the Cholesky factor of M, all eigenvalues by eigvalsh.
"""
import os
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def block(n, k, arms):
    """The 12 x 12 tangent block of one spring."""
    k_n, k_t, k_r, k_w = k
    eye = np.eye(3)
    p = eye - np.outer(n, n)
    b = np.concatenate([-n, np.zeros(3), n, np.zeros(3)])
    bt = np.hstack([-p, arms[0] * skew(n), p, arms[1] * skew(n)])
    d = np.hstack([np.zeros((3, 3)), -eye, np.zeros((3, 3)), eye])
    return (k_n * np.outer(b, b) + k_t * bt.T @ bt
            + d.T @ (k_r * p + k_w * np.outer(n, n)) @ d)


def spectrum(kk, mm):
    ell = np.linalg.cholesky(mm)
    li = np.linalg.inv(ell)
    a = li @ kk @ li.T
    return np.linalg.eigvalsh(0.5 * (a + a.T))


def clumps(rng, n_bodies, k_n, k_t, rolling, twisting):
    """Clumps of 1 to 3 overlapping spheres on a jittered grid over a floor."""
    side = int(np.ceil(n_bodies ** (1.0 / 3.0) - 1e-9))
    x, r, m, body = [], [], [], []
    for b in range(n_bodies):
        centre = 1.9 * np.array([b % side, (b // side) % side, b // side ** 2], float) \
            + 0.3 * (rng.random(3) - 0.5)
        for j in range(rng.integers(1, 4)):
            u = rng.random(3) - 0.5
            pos = centre if j == 0 else centre + (0.5 + 0.6 * abs(u[0])) * u / np.linalg.norm(u)
            rad = 0.7 + 0.3 * rng.random()
            x.append(pos)
            r.append(rad)
            m.append(rad ** 3 * (0.6 + 0.8 * rng.random()))
            body.append(b + 1)
    x, r, m, body = np.array(x), np.array(r), np.array(m), np.array(body)
    floor = float(np.min(x[:, 2] - r) + 0.05)
    n = len(r)
    # bodies: mass, centre, tensor (Yade's sum)
    nb = n_bodies
    mass = np.zeros(nb)
    com = np.zeros((nb, 3))
    for i in range(n):
        mass[body[i] - 1] += m[i]
        com[body[i] - 1] += m[i] * x[i]
    com /= mass[:, None]
    jj = np.zeros((nb, 3, 3))
    for i in range(n):
        d = x[i] - com[body[i] - 1]
        jj[body[i] - 1] += 0.4 * m[i] * r[i] ** 2 * np.eye(3) + m[i] * (d @ d * np.eye(3) - np.outer(d, d))
    kk = np.zeros((6 * nb, 6 * nb))
    mm = np.zeros((6 * nb, 6 * nb))
    for b in range(nb):
        mm[6 * b:6 * b + 3, 6 * b:6 * b + 3] = mass[b] * np.eye(3)
        mm[6 * b + 3:6 * b + 6, 6 * b + 3:6 * b + 6] = jj[b]

    def rigid(i):
        t = np.eye(6)
        t[0:3, 3:6] = -skew(x[i] - com[body[i] - 1])
        return t, 6 * (body[i] - 1)

    def add(blk, ends):
        g = np.zeros((12, 6 * nb))
        for e, i in enumerate(ends):
            if i is None:
                continue
            t, o = rigid(i)
            g[6 * e:6 * e + 6, o:o + 6] = t
        kk[:, :] += g.T @ blk @ g

    contacts = 0
    for i in range(n):
        for j in range(i + 1, n):
            if body[i] == body[j]:
                continue
            d = x[j] - x[i]
            dist = np.linalg.norm(d)
            ov = r[i] + r[j] - dist
            if ov <= 0.0:
                continue
            rs = r[i] * r[j] / (r[i] + r[j])
            add(block(d / dist, (k_n, k_t, rolling * k_t * rs ** 2, twisting * k_t * rs ** 2),
                      (r[i] - ov / 2, r[j] - ov / 2)), (i, j))
            contacts += 1
        ov = r[i] - (x[i, 2] - floor)
        if ov > 0.0:
            add(block(np.array([0.0, 0.0, 1.0]), (k_n, k_t, rolling * k_t * r[i] ** 2, twisting * k_t * r[i] ** 2),
                      (0.0, r[i] - ov / 2)), (None, i))
            contacts += 1
    return x, r, m, body, floor, contacts, spectrum(kk, mm)


def bonded(rng, side, model, params):
    """A jittered cubic lattice of spheres (radii 1 +- 15 %), a bond between
    every pair closer than 1.1 (r_i + r_j): gaps and overlaps."""
    x, r, m = [], [], []
    for a in range(side):
        for b in range(side):
            for c in range(side):
                x.append(2.0 * np.array([a, b, c], float) + 0.3 * (rng.random(3) - 0.5))
                rad = 0.85 + 0.3 * rng.random()
                r.append(rad)
                m.append(rad ** 3 * (0.6 + 0.8 * rng.random()))
    x, r, m = np.array(x), np.array(r), np.array(m)
    n = len(r)
    kk = np.zeros((6 * n, 6 * n))
    mm = np.diag(np.concatenate([[m[i]] * 3 + [0.4 * m[i] * r[i] ** 2] * 3 for i in range(n)]))
    pairs = []
    for i in range(n):
        for j in range(i + 1, n):
            d = x[j] - x[i]
            length = np.linalg.norm(d)
            if length >= 1.1 * (r[i] + r[j]):
                continue
            pairs.append((i + 1, j + 1))
            ov = r[i] + r[j] - length
            if model == "pfc":
                kbar_n, kbar_s, lam = params
                rb = lam * min(r[i], r[j])
                area, i2, j2 = np.pi * rb ** 2, 0.25 * np.pi * rb ** 4, 0.5 * np.pi * rb ** 4
                k = (kbar_n * area, kbar_s * area, kbar_n * i2, kbar_s * j2)
            else:
                young, poisson, a_kr, a_ktw = params
                kn = 2.0 * young * r[i] * r[j] / (r[i] + r[j])
                ks = poisson * kn
                k = (kn, (r[i] + r[j]) / length * ks, r[i] * r[j] * ks * a_kr, r[i] * r[j] * ks * a_ktw)
            blk = block(d / length, k, (r[i] - ov / 2, r[j] - ov / 2))
            idx = np.r_[6 * i:6 * i + 6, 6 * j:6 * j + 6]
            kk[np.ix_(idx, idx)] += blk
    return x, r, m, pairs, spectrum(kk, mm)


def main():
    rng = np.random.default_rng(20261126)
    law = (1.0e3, 400.0, 0.1, 0.05)
    for t, nb in enumerate((8, 12, 18), start=1):
        x, r, m, body, floor, contacts, lam = clumps(rng, nb, *law)
        with open(os.path.join(HERE, "clumps_%d.txt" % t), "w") as f:
            f.write("%d %d %d %.17g %.17g %.17g %.17g %.17g   "
                    "! spheres bodies springs floor_z k_n k_t rolling twisting\n"
                    % (len(r), nb, contacts, floor, *law))
            for i in range(len(r)):
                f.write("%.17g %.17g %.17g %.17g %.17g %d\n" % (*x[i], m[i], r[i], body[i]))
            f.write("".join("%.17g\n" % v for v in lam))
    for t, (model, params) in enumerate((("pfc", (1.0e4, 4.0e3, 0.8)), ("yade", (1.0e4, 0.3, 2.0, 2.0))),
                                        start=1):
        x, r, m, pairs, lam = bonded(rng, 3, model, params)
        with open(os.path.join(HERE, "bonds_%d.txt" % t), "w") as f:
            f.write("%d %d %s %s   ! spheres bonds model parameters\n"
                    % (len(r), len(pairs), model, " ".join("%.17g" % p for p in params)))
            for i in range(len(r)):
                f.write("%.17g %.17g %.17g %.17g %.17g\n" % (*x[i], m[i], r[i]))
            f.write("".join("%d %d\n" % p for p in pairs))
            f.write("".join("%.17g\n" % v for v in lam))


if __name__ == "__main__":
    main()
