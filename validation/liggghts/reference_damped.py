#!/usr/bin/env python3
"""Independent numpy/scipy reference for the LIGGGHTS validation scenes.

From a scene's settled state (data/<scene>/particles.csv, pairs.csv,
walls.csv, materials.json) it builds the linearised stiffness K and dashpot
matrix C with 6 degrees of freedom per sphere (3 translations, 3 rotations),
following LIGGGHTS 3.8's conventions (CONVENTIONS.md), and computes

  (i)  the undamped limit      h0 = 2 / sqrt(lambda_max(A)),
  (ii) the exact damped limit  h*: the smallest h with
       lambda_max(h^2 A + 2 h B) = 4,
  with A = M^-1/2 K M^-1/2 and B = M^-1/2 C M^-1/2.

No demstep code is used.  Writes data/<scene>/reference.json and results.md
(the table against data/measured.csv).

Variants reported besides the full model ("stick"):
  "slide"   contacts whose elastic tangential force is at the Coulomb limit
            (k_t |s| >= 0.999 mu F_n, the test LIGGGHTS makes) lose their
            tangential spring and dashpot, and epsd2 rolling springs at the
            torque cap lose theirs: LIGGGHTS applies neither there;
  "normal"  normal springs and dashpots only (no tangential or rolling terms).

Usage: python3 reference_damped.py [--table] [scene ...]
  (default: every scene with data; --table rewrites results.md from the
  stored reference.json files without solving again)
"""
import json
import math
import os
import sys

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")
SCENES = ["a_hertz", "b_hooke", "c_epsd2", "d_periodic", "e_undamped", "f_tdoff", "g_hooke_undamped"]
SQRT56 = math.sqrt(5.0 / 6.0)
INERTIA = 0.4          # fix nve/sphere: I = 0.4 m r^2
STICK_LIMIT = 0.999    # fraction of the Coulomb (or rolling) limit called sliding


def read_csv(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
        rows = [l.strip().split(",") for l in f if l.strip()]
    cols = {}
    for k, n in enumerate(names):
        vals = [r[k] for r in rows]
        try:
            cols[n] = np.array([float(v) for v in vals])
        except ValueError:
            cols[n] = np.array(vals)
    return cols


def cross_matrix(n):
    """[n]x with [n]x a = n x a."""
    return np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])


class Material:
    """LIGGGHTS 3.8 contact coefficients for one type pair (both type 1)."""

    def __init__(self, m):
        self.m = m
        Y, nu = m["youngs_modulus"], m["poisson_ratio"]
        # global_properties.cpp createYeff / createGeff with both sides alike
        self.Yeff = 1.0 / (2.0 * (1.0 - nu * nu) / Y)
        self.Geff = 1.0 / (2.0 * 2.0 * (2.0 - nu) * (1.0 + nu) / Y)
        e = m["coefficient_restitution"]
        self.loge = math.log(e)
        self.beta = self.loge / math.sqrt(self.loge ** 2 + math.pi ** 2)
        self.mu = m["coefficient_friction"]
        self.rmu = m["coefficient_rolling_friction"]
        self.model = m["model"]
        self.tdamp = m["tangential_damping"]
        self.rolling = m["rolling_friction"]

    def contact(self, reff, meff, delta):
        """(Fn elastic, tangent normal stiffness, k_t, gamma_n, gamma_t)."""
        if self.model == "hertz":
            sq = math.sqrt(reff * delta)
            Sn = 2.0 * self.Yeff * sq            # dF_n/d(delta)
            St = 8.0 * self.Geff * sq            # k_t
            kn = 4.0 / 3.0 * self.Yeff * sq      # secant: F_n = kn delta
            gn = -2.0 * SQRT56 * self.beta * math.sqrt(Sn * meff)
            gt = -2.0 * SQRT56 * self.beta * math.sqrt(St * meff) if self.tdamp else 0.0
            return kn * delta, Sn, St, gn, gt
        if self.model == "hooke":
            v = self.m["characteristic_velocity"]
            sr = math.sqrt(reff)
            kn = 16.0 / 15.0 * sr * self.Yeff * (15.0 * meff * v * v / (16.0 * sr * self.Yeff)) ** 0.2
            l2 = self.loge ** 2
            gn = math.sqrt(4.0 * meff * kn * l2 / (l2 + math.pi ** 2))
            gt = gn if self.tdamp else 0.0
            return kn * delta, kn, kn, gn, gt
        raise ValueError("model %s" % self.model)


def assemble(scene, variant="stick"):
    d = os.path.join(DATA, scene)
    with open(os.path.join(d, "materials.json")) as f:
        mat = json.load(f)
    M = Material(mat)
    p = read_csv(os.path.join(d, "particles.csv"))
    ids = p["id"].astype(int)
    row = {i: k for k, i in enumerate(ids)}
    n = len(ids)
    x = np.c_[p["x"], p["y"], p["z"]]
    rad, mass = p["radius"], p["mass"]
    inertia = INERTIA * mass * rad ** 2
    mdiag = np.c_[mass, mass, mass, inertia, inertia, inertia].ravel()
    Ki, Kj, Kv, Ci, Cj, Cv = [], [], [], [], [], []
    stats = dict(pairs=0, walls=0, pairs_sliding=0, walls_sliding=0, rolling_at_cap=0)
    fn_err, ft_err, dl_err = [], [], []

    def add(dofs, G, k, c):
        """K += k G^T G, C += c G^T G on the listed dofs."""
        blk = G.T @ G
        I, J = np.meshgrid(dofs, dofs, indexing="ij")
        if k != 0.0:
            Ki.append(I.ravel()); Kj.append(J.ravel()); Kv.append((k * blk).ravel())
        if c != 0.0:
            Ci.append(I.ravel()); Cj.append(J.ravel()); Cv.append((c * blk).ravel())

    def one_contact(dofs, nvec, ci, cj, reff, meff, delta, shear, fn_dump, ft_dump, rt_dump,
                    wall, roll_scale):
        Fn, kn, kt, gn, gt = M.contact(reff, meff, delta)
        # check the convention against LIGGGHTS's own forces where they were dumped
        if fn_dump is not None and Fn > 0:
            fn_err.append(abs(fn_dump - Fn) / Fn)
        s = np.linalg.norm(shear)
        sliding = kt * s >= STICK_LIMIT * M.mu * Fn
        if ft_dump is not None and not sliding and kt * s > 1e-3 * Fn:
            ft_err.append(abs(ft_dump - kt * s) / (kt * s))
        stats["walls_sliding" if wall else "pairs_sliding"] += int(sliding)
        P = np.eye(3) - np.outer(nvec, nvec)
        X = cross_matrix(nvec)
        Z = np.zeros((3, 3))
        if wall:
            Gn = np.r_[nvec, np.zeros(3)][None, :]
            Gt = np.c_[P, ci * X]
        else:
            Gn = np.r_[nvec, np.zeros(3), -nvec, np.zeros(3)][None, :]
            Gt = np.c_[P, ci * X, -P, cj * X]
        add(dofs, Gn, kn, gn)
        if variant == "normal":
            return
        if not (variant == "slide" and sliding):
            add(dofs, Gt, kt, gt)
        if M.rolling == "epsd2":
            kr = kt * reff * reff          # rolling_model_epsd2.h: kr = kt reff^2
            at_cap = rt_dump is not None and np.linalg.norm(rt_dump) >= STICK_LIMIT * M.rmu * reff * Fn
            stats["rolling_at_cap"] += int(at_cap)
            if variant == "slide" and at_cap:
                return
            if wall:
                Gr = np.c_[Z, roll_scale * P]
            else:
                Gr = np.c_[Z, P, Z, -P]
            add(dofs, Gr, kr, 0.0)
        elif M.rolling not in ("off", None):
            raise ValueError("rolling model %s not in this reference" % M.rolling)

    periodic = any(mat["periodic"])
    box = np.array(mat["box_hi"]) - np.array(mat["box_lo"])
    c = read_csv(os.path.join(d, "pairs.csv"))
    hist = ["shear_x", "shear_y", "shear_z"]
    rth = ["rtorque_x", "rtorque_y", "rtorque_z"]
    for k in range(len(c["id1"])):
        a, b = row[int(c["id1"][k])], row[int(c["id2"][k])]
        # LIGGGHTS' x2 is particle 2's own (wrapped) position, also across a
        # periodic boundary (periodic = 1): take the nearest image
        dvec = x[a] - x[b]
        if periodic:
            dvec -= box * np.round(dvec / box)
        r = np.linalg.norm(dvec)
        delta = rad[a] + rad[b] - r
        if delta <= 0.0:
            continue
        dl_err.append(abs(delta - c["delta"][k]) / c["delta"][k])
        nvec = dvec / r                                      # from 2 to 1, as LIGGGHTS' en
        reff = rad[a] * rad[b] / (rad[a] + rad[b])
        meff = mass[a] * mass[b] / (mass[a] + mass[b])
        ci, cj = rad[a] - 0.5 * delta, rad[b] - 0.5 * delta  # surface_model_default.h
        dofs = np.r_[6 * a + np.arange(6), 6 * b + np.arange(6)]
        shear = np.array([c[h][k] for h in hist])
        fn = np.linalg.norm([c["fnx"][k], c["fny"][k], c["fnz"][k]])
        ft = np.linalg.norm([c["ftx"][k], c["fty"][k], c["ftz"][k]])
        rt = np.array([c[h][k] for h in rth]) if rth[0] in c else None
        one_contact(dofs, nvec, ci, cj, reff, meff, delta, shear,
                    fn, ft, rt, False, 1.0)
        stats["pairs"] += 1
    wpath = os.path.join(d, "walls.csv")
    if os.path.exists(wpath):
        w = read_csv(wpath)
        for k in range(len(w["id"])):
            a = row[int(w["id"][k])]
            ax = "xyz".index(w["axis"][k])
            nvec = np.zeros(3)
            nvec[ax] = float(w["normal_sign"][k])           # from the wall into the box
            delta = float(w["delta"][k])
            if delta <= 0.0:
                continue
            cr = rad[a] - 0.5 * delta                       # surface_model_default.h (wall)
            dist = rad[a] - delta                           # fix_wall_gran_base.h: r
            dofs = 6 * a + np.arange(6)
            shear = np.array([w[h][k] for h in hist])
            rt = np.array([w[h][k] for h in rth]) if rth[0] in w else None
            one_contact(dofs, nvec, cr, 0.0, rad[a], mass[a], delta, shear, None, None, rt, True,
                        cr / dist)
            stats["walls"] += 1
    # how well the conventions reproduce LIGGGHTS' own dumped pair forces:
    # |F_n| against the elastic k_n delta, |F_t| against k_t |shear| (sticking
    # contacts); the dumped forces also hold the dashpots' part, so moving
    # particles widen these (median and 99th percentile of relative errors)
    for key, e in (("fn", fn_err), ("ft", ft_err), ("delta", dl_err)):
        stats[key + "_check_median"] = float(np.median(e)) if e else 0.0
        stats[key + "_check_p99"] = float(np.percentile(e, 99)) if e else 0.0
    N = 6 * n
    K = sp.coo_matrix((np.concatenate(Kv), (np.concatenate(Ki), np.concatenate(Kj))), shape=(N, N)).tocsr()
    if Cv:
        C = sp.coo_matrix((np.concatenate(Cv), (np.concatenate(Ci), np.concatenate(Cj))), shape=(N, N)).tocsr()
    else:
        C = sp.csr_matrix((N, N))
    s = sp.diags(1.0 / np.sqrt(mdiag))
    A = (s @ K @ s).tocsr()
    B = (s @ C @ s).tocsr()
    return A, B, stats, n


def lam_max(S, v0=None):
    vals, vecs = eigsh(S, k=1, which="LA", tol=1e-12, v0=v0, maxiter=20000, ncv=40)
    return vals[0], vecs[:, 0]


def limits(A, B):
    la, v = lam_max(A)
    h0 = 2.0 / math.sqrt(la)
    if B.nnz == 0:
        return h0, h0, 0
    # Newton on f(h) = lambda_max(h^2 A + 2 h B) - 4 from h0 (f(h0) >= 0);
    # f is increasing and convex enough that Newton from above is monotone,
    # and a bisection bracket is kept as a guard.
    lo, hi = 0.0, h0
    h, it = h0, 0
    for it in range(1, 60):
        lam, v = lam_max(h * h * A + 2.0 * h * B, v)
        f = lam - 4.0
        if f > 0:
            hi = min(hi, h)
        else:
            lo = max(lo, h)
        if abs(f) < 1e-11 * 4.0:
            break
        df = v @ (2.0 * h * (A @ v) + 2.0 * (B @ v))
        hn = h - f / df
        h = hn if lo < hn < hi else 0.5 * (lo + hi)
        if hi - lo < 1e-13 * hi:
            break
    return h0, h, it


def dense_check(A, B, h):
    """Dense eigvalsh of h^2 A + 2 h B at the answer (should be 4)."""
    S = (h * h * A + 2.0 * h * B).toarray()
    return float(np.linalg.eigvalsh(S)[-1])


def measured(suffix=""):
    out = {}
    path = os.path.join(DATA, "measured%s.csv" % suffix)
    if not os.path.exists(path):
        return out
    with open(path) as f:
        f.readline()
        for line in f:
            w = line.split(",")
            out[w[0]] = (float(w[1]), float(w[2]))
    return out


def main():
    args = sys.argv[1:]
    table_only = "--table" in args
    args = [a for a in args if a != "--table"]
    scenes = args or [s for s in SCENES if os.path.exists(os.path.join(DATA, s, "particles.csv"))]
    results = {}
    for sc in scenes:
        path = os.path.join(DATA, sc, "reference.json")
        if table_only:
            with open(path) as f:
                results[sc] = json.load(f)
            continue
        res = {}
        for variant in ("stick", "slide", "normal"):
            A, B, stats, n = assemble(sc, variant)
            h0, h, it = limits(A, B)
            res[variant] = dict(undamped=h0, damped=h, newton_iterations=it)
            if variant == "stick":
                res["stats"] = stats
                res["particles"] = n
                res["dense_lambda_at_damped"] = dense_check(A, B, h)
        with open(path, "w") as f:
            json.dump(res, f, indent=1)
            f.write("\n")
        results[sc] = res
        st = res["stats"]
        print("%-11s n %d pairs %d (sliding %d) walls %d (sliding %d) rolling at cap %d; "
              "Fn check median %.1e p99 %.1e, Ft check median %.1e p99 %.1e; undamped %.5e damped %.5e "
              "(dense lambda %.12f)" % (
                  sc, n, st["pairs"], st["pairs_sliding"], st["walls"], st["walls_sliding"],
                  st["rolling_at_cap"], st["fn_check_median"], st["fn_check_p99"],
                  st["ft_check_median"], st["ft_check_p99"],
                  res["stick"]["undamped"], res["stick"]["damped"], res["dense_lambda_at_damped"]))
        sys.stdout.flush()
    write_results(results, measured(), measured("_factor2"), measured("_kick1e-06"))


def write_results(results, meas, meas2, meas3):
    lines = ["# LIGGGHTS 3.8 validation: measured and modelled largest stable time step", "",
             "Written by `reference_damped.py` from `data/measured.csv`, `data/measured_factor2.csv` "
             "`data/measured_kick1e-06.csv` and `data/<scene>/reference.json`. Measured: bisection in "
             "LIGGGHTS (README.md gives the criterion; factor 10 with a 1e-4 m/s kick is the main one, "
             "factor 2 the more sensitive one, and a 1e-6 m/s kick, factor 10, was run on the undamped "
             "controls). Model: "
             "6 degrees of freedom per sphere, LIGGGHTS' conventions (CONVENTIONS.md). Ratios are "
             "model / measured with the measured limit taken as the middle of its bracket.", "",
             "| scene | measured [lo, hi] (s), factor 10 | model undamped (s) | model damped (s) "
             "| damped / measured | undamped / measured | measured [lo, hi] (s), factor 2 "
             "| damped / measured (factor 2) | measured [lo, hi] (s), kick 1e-6 | damped / measured (kick 1e-6) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for sc, res in results.items():
        if sc not in meas:
            continue
        lo, hi = meas[sc]
        mid = 0.5 * (lo + hi)
        st = res["stick"]
        if sc in meas2:
            lo2, hi2 = meas2[sc]
            mid2 = 0.5 * (lo2 + hi2)
            extra = "[%.4e, %.4e] | %.4f" % (lo2, hi2, st["damped"] / mid2)
        else:
            extra = "not run | -"
        if sc in meas3:
            lo3, hi3 = meas3[sc]
            extra += " | [%.4e, %.4e] | %.4f" % (lo3, hi3, st["damped"] / (0.5 * (lo3 + hi3)))
        else:
            extra += " | not run | -"
        lines.append("| %s | [%.4e, %.4e] | %.4e | %.4e | %.4f | %.4f | %s |" % (
            sc, lo, hi, st["undamped"], st["damped"], st["damped"] / mid, st["undamped"] / mid, extra))
    lines += ["", "Variants of the model (damped limit / measured, factor 10): sliding contacts "
              "(elastic tangential force at 0.999 of the Coulomb limit, or epsd2 torque at its cap) "
              "freed of their tangential or rolling terms; normal springs and dashpots only.", "",
              "| scene | pair contacts (sliding) | wall contacts (sliding) | rolling at cap "
              "| stick | sliding freed | normal only | F_n check median / p99 | F_t check median / p99 |",
              "|---|---|---|---|---|---|---|---|---|"]
    for sc, res in results.items():
        if sc not in meas:
            continue
        lo, hi = meas[sc]
        mid = 0.5 * (lo + hi)
        st = res["stats"]
        lines.append("| %s | %d (%d) | %d (%d) | %d | %.4f | %.4f | %.4f | %.1e / %.1e | %.1e / %.1e |" % (
            sc, st["pairs"], st["pairs_sliding"], st["walls"], st["walls_sliding"], st["rolling_at_cap"],
            res["stick"]["damped"] / mid, res["slide"]["damped"] / mid, res["normal"]["damped"] / mid,
            st["fn_check_median"], st["fn_check_p99"], st["ft_check_median"], st["ft_check_p99"]))
    lines += ["", "Every measurement (each `data/measured*.csv`): kick = sigma of the velocity kick, "
              "F = late-energy factor.", "",
              "| scene | kick (m/s) | F | measured [lo, hi] (s) | model damped (s) | model / measured |",
              "|---|---|---|---|---|---|"]
    for suffix, kick, fac in (("", 1e-4, 10), ("_factor2", 1e-4, 2), ("_kick1e-06", 1e-6, 10),
                              ("_kick1e-06_factor2", 1e-6, 2)):
        m = measured(suffix)
        for sc, res in results.items():
            if sc in m:
                lo, hi = m[sc]
                lines.append("| %s | %g | %g | [%.4e, %.4e] | %.4e | %.4f |" % (
                    sc, kick, fac, lo, hi, res["stick"]["damped"], res["stick"]["damped"] / (0.5 * (lo + hi))))
    with open(os.path.join(HERE, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
