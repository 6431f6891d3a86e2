#!/usr/bin/env python3
"""The peers' rules on the `fix multisphere` scenes (h_multisphere,
i_multisphere3), through demstep's Python package: Yade's
GlobalStiffnessTimeStepper and exaDEM's rule on the same rigid bodies
(`Scene.body_peer_steps`, the library's `body_gst_step` and
`body_exadem_step`, raw), demstep's exact limits with the bodies given
explicitly (a cross-check of the app's `mol` reading), and the members taken
as free spheres. Writes demstep/multisphere_peers.md. For j_multisphere_mc
(the template left to LIGGGHTS' Monte Carlo) the bodies are the union of
their two equal spheres in closed form (the app's `body_union`, which
integrates numerically), and a last row gives the library LIGGGHTS' own
estimate instead (the union's mass and principal moments from its log, the
tensor axisymmetric about the two members' axis).

    DEMSTEP_LIBRARY=path/to/libdemstep.so.0 python3 multisphere_peers.py

The bodies are built here from the dump as LIGGGHTS has them (its template
states them, see README.md): membership from `mol`, the body's mass from
`mass`, the members sharing it in proportion to r^3, centre and tensor the
members' sum with Steiner's term (h, i) or the union's (j)."""
import csv
import json
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "..", "python"))
import demstep  # noqa: E402

SCENES = ("h_multisphere", "i_multisphere3", "j_multisphere_mc")


def bodies(rows):
    """body_of (1..nb), mass, com, inertia of the rows' bodies (mol order)."""
    mol = np.array([int(r["mol"]) for r in rows])
    ids = sorted(set(mol))
    body_of = np.array([ids.index(k) + 1 for k in mol])
    x = np.array([[float(r[k]) for k in ("x", "y", "z")] for r in rows])
    rad = np.array([float(r["radius"]) for r in rows])
    mb = np.array([float(r["mass"]) for r in rows])
    nb = len(ids)
    mass, com, inertia = np.zeros(nb), np.zeros((nb, 3)), np.zeros((nb, 3, 3))
    for b in range(nb):
        k = body_of == b + 1
        m = mb[k] * rad[k] ** 3 / np.sum(rad[k] ** 3)
        mass[b] = mb[k][0]
        com[b] = m @ x[k] / m.sum()
        for mi, xi, ri in zip(m, x[k], rad[k]):
            d = xi - com[b]
            inertia[b] += 0.4 * mi * ri * ri * np.eye(3) + mi * (d @ d * np.eye(3) - np.outer(d, d))
    return body_of, mass, com, inertia, x, rad, mb


def union_pair_bodies(rows):
    """Bodies of two equal overlapping spheres (r, centres d apart) as their
    union at the dump's body mass: each sphere less the cap of height
    h = r - d/2 beyond the mid-plane. Volume 2 (4/3 pi r^3 - pi h^2 (3 r - h)
    / 3); axial moment per unit density 2 (8/15 pi r^5 - pi h^3 (20 r^2 -
    15 r h + 3 h^2) / 30) (a cap's moment about its axis); transverse half
    of it plus 2 int x^2 over a half (x = u + d/2, slice area pi (r^2 - u^2),
    u from -d/2 to r); centre at the midpoint."""
    body_of, mass, com, _, x, rad, _ = bodies(rows)
    nb = body_of.max()
    inertia = np.zeros((nb, 3, 3))
    for b in range(nb):
        k = body_of == b + 1
        (xa, xb), (ra, rb) = x[k], rad[k]
        assert ra == rb, "union_pair_bodies: two equal spheres"
        r, d = ra, np.linalg.norm(xb - xa)
        h, a = r - d / 2, d / 2
        vol = 2 * (4 / 3 * np.pi * r ** 3 - np.pi * h * h * (3 * r - h) / 3)
        axial = 2 * (8 / 15 * np.pi * r ** 5 - np.pi * h ** 3 * (20 * r * r - 15 * r * h + 3 * h * h) / 30)

        def half(u):
            return np.pi * (r * r * u ** 3 / 3 - u ** 5 / 5 + 2 * a * (r * r * u ** 2 / 2 - u ** 4 / 4)
                            + a * a * (r * r * u - u ** 3 / 3))
        transverse = 0.5 * axial + 2 * (half(r) - half(-a))
        n = (xb - xa) / d
        nn = np.outer(n, n)
        inertia[b] = mass[b] / vol * (axial * nn + transverse * (np.eye(3) - nn))
        com[b] = 0.5 * (xa + xb)
    return mass, com, inertia


def logged_bodies(mat, rows):
    """j_multisphere_mc's bodies as LIGGGHTS estimated them (its log): mass,
    principal moments (axial, and the mean of the two transverse ones, equal
    but for the estimate's noise, 9e-4 apart); the centre at the members'
    midpoint (the log puts it 4.7e-7 m, 4e-4 of a radius, away)."""
    log = mat["bodies"]["liggghts_log"]
    m = float(log[1].split("=")[1].split(",")[0])
    moments = [float(v) for v in log[4].split(":")[1].split(",")]
    body_of, _, com, _, x, _, _ = bodies(rows)
    nb = body_of.max()
    inertia = np.zeros((nb, 3, 3))
    for b in range(nb):
        xa, xb = x[body_of == b + 1]
        n = (xb - xa) / np.linalg.norm(xb - xa)
        nn = np.outer(n, n)
        inertia[b] = moments[0] * nn + 0.5 * (moments[1] + moments[2]) * (np.eye(3) - nn)
    return np.full(nb, m), com, inertia


def scene(mat, rows, with_bodies, logged=False):
    body_of, mass, com, inertia, x, rad, mb = bodies(rows)
    if logged:
        mass, com, inertia = logged_bodies(mat, rows)
    elif "mass" not in mat["bodies"]:
        mass, com, inertia = union_pair_bodies(rows)
    radii = sorted(set(mat["radii"]))
    types = np.array([min(range(len(radii)), key=lambda k: abs(r - radii[k])) for r in rad])
    s = demstep.Scene(3)
    s.set_particles(x, mb, rad)
    n = len(radii)
    s.set_materials(types, [mat["youngs_modulus"]] * n, [mat["poisson_ratio"]] * n, [mat["density"]] * n,
                    radii, "liggghts_hertz", mat["coefficient_restitution"], 1.0, wall_type=0)
    pts, nrm = [], []
    for w in mat["walls"]:
        a = "xyz".index(w["plane"][0])
        p, q = [0.0] * 3, [0.0] * 3
        p[a], q[a] = w["position"], float(w["inward_normal_sign"])
        pts.append(p)
        nrm.append(q)
    s.add_walls(np.array(pts), np.array(nrm))
    s.set_effects(["contacts", "rotation", "walls", "damping"])
    if with_bodies:
        s.set_bodies(body_of, mass=mass, com=com, inertia=inertia)
    return s


def main():
    measured = {r["scene"]: r for r in csv.DictReader(open(os.path.join(here, "data", "measured.csv")))}
    lines = ["| scene | bodies (members) | measured [lo, hi] s | demstep exact damped / measured | undamped "
             "/ measured | Yade GST raw / measured | exaDEM raw / measured | members as free spheres "
             "(mass column as theirs), damped / measured |",
             "|---|---|---|---|---|---|---|---|"]
    for sc in SCENES:
        mat = json.load(open(os.path.join(here, "data", sc, "materials.json")))
        rows = list(csv.DictReader(open(os.path.join(here, "data", sc, "particles.csv"))))
        lo, hi = float(measured[sc]["dt_measured_lo"]), float(measured[sc]["dt_measured_hi"])
        mid = 0.5 * (lo + hi)
        with scene(mat, rows, True) as s:
            r = s.compute("current")
            gst, exa = s.body_peer_steps()
        with scene(mat, rows, False) as s:
            free = s.compute("current")
        nb = len(set(x["mol"] for x in rows))
        lines.append("| %s | %d (%d) | [%.5g, %.5g] | %.4f (%.5g s) | %.4f | %.4f | %.4f | %.4f |" % (
            sc, nb, len(rows), lo, hi, r.dt_critical_damped / mid, r.dt_critical_damped,
            r.dt_critical_eigen / mid, gst / mid, exa / mid, free.dt_critical_damped / mid))
        if "liggghts_log" in mat["bodies"]:
            with scene(mat, rows, True, logged=True) as s:
                r = s.compute("current")
                gst, exa = s.body_peer_steps()
            lines.append("| %s, LIGGGHTS' logged mass and tensor | %d (%d) | [%.5g, %.5g] | %.4f (%.5g s) | %.4f "
                         "| %.4f | %.4f | |" % (sc, nb, len(rows), lo, hi, r.dt_critical_damped / mid,
                                              r.dt_critical_damped, r.dt_critical_eigen / mid, gst / mid, exa / mid))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(here, "demstep", "multisphere_peers.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
