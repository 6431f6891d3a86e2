#!/usr/bin/env python3
"""Give demstep the Yade clump packing (data/clumps, from yade_clumps.py) as a
user would: the members as a particle table, their contacts between clumps
with Yade's own kn, ks as an explicit contact list, the clump table as
`bodies_file`, and the five walls with the wall contacts' kn, ks as the
scene's law. Runs the app twice (as rigid bodies, and as free spheres on the
same contacts) and compares with the limit measured in Yade, with Yade's
GlobalStiffnessTimeStepper (raw) and with exaDEM's rule (raw).

    python3 validation/yade/demstep_compare_clumps.py [path/to/demstep]

Writes validation/yade/demstep/clumps.nml, clumps_spheres.nml, their
_result.nml and clumps_comparison.md. Needs only python3."""
import json, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "demstep")
data = os.path.join(here, "data", "clumps")


def scalar(path, key):
    text = open(path).read()
    k = text.upper().index(key.upper() + "=")
    return float(text[k + len(key) + 1:].split(",")[0])


def deck(name, bodies):
    walls = json.load(open(os.path.join(data, "walls.json")))
    if len(walls["k_n"]) != 1 or len(walls["k_t"]) != 1:
        sys.exit("the wall contacts do not share one k_n and one k_t: %s" % walls)
    values = []
    for p, n in zip(walls["points"], walls["normals"]):
        values.append(", ".join("%.17g" % v for v in list(p) + list(n)))
    with open(os.path.join(out, name + ".nml"), "w") as f:
        f.write("! Yade clump packing, settled; written by demstep_compare_clumps.py\n")
        f.write("&scene\n  dim = 3\n  particles_file = '../data/clumps/particles.txt'\n")
        f.write("  contacts_file = '../data/clumps/contacts.txt'\n")
        if bodies:
            f.write("  bodies_file = '../data/clumps/bodies.txt'\n")
        f.write("  effects = 'contacts', 'walls', 'rotation'\n")
        f.write("  walls = " + ",\n    ".join(values) + "\n")
        f.write("  k_normal = %.17g, k_tangential = %.17g   ! the wall contacts' own\n"
                % (walls["k_n"][0], walls["k_t"][0]))
        f.write("  eigen_solver = 'dense'\n/\n")


def exadem_step():
    """exaDEM's critical step pi sqrt(m_min/k_n,max) (Collab4exaNBody/exaDEM at
    0d0dc65, src/field/check_dt_critical.cpp:92; demstep's `exadem_step`):
    the lightest clump (its members' masses summed, as Yade and demstep's
    `bodies_from_members` do) and the stiffest contact, walls included."""
    import math
    rows = [l.split() for l in open(os.path.join(data, "particles.txt")) if not l.startswith("#")]
    mass = [float(r[6]) for r in rows]
    body = {}
    for l in open(os.path.join(data, "bodies.txt")):
        if l.startswith("#"):
            continue
        i, b = (int(v) for v in l.split())
        body[b] = body.get(b, 0.0) + mass[i - 1]
    k_n = [float(l.split()[2]) for l in open(os.path.join(data, "contacts.txt")) if not l.startswith("#")]
    k_n += json.load(open(os.path.join(data, "walls.json")))["k_n"]
    return math.pi * math.sqrt(min(body.values()) / max(k_n))


def main():
    app = sys.argv[1] if len(sys.argv) > 1 else "demstep"
    os.makedirs(out, exist_ok=True)
    s = json.load(open(os.path.join(data, "summary.json")))
    lo, hi = s["measured_dt_lo"], s["measured_dt_hi"]
    mid = 0.5 * (lo + hi)
    res = {}
    for name, bodies in (("clumps", True), ("clumps_spheres", False)):
        deck(name, bodies)
        result = os.path.join(out, name + "_result.nml")
        run = subprocess.run([app, "-q", os.path.join(out, name + ".nml"), "-o", result],
                             capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(name + ": " + run.stdout[-1000:] + run.stderr[-1000:])
        res[name] = {k: scalar(result, k) for k in ("dt_critical_eigen", "dt_critical_bound", "dt_contact_rule")}
    c, sp = res["clumps"], res["clumps_spheres"]
    gst = s["GlobalStiffnessTimeStepper_raw"]
    exadem = exadem_step()
    lines = ["| scene | clumps (members) | contacts (+ walls) | Yade measured [lo, hi] s | demstep exact (bodies) s "
             "| / measured | bound / measured | GST raw / measured | exaDEM raw / measured "
             "| members as free spheres / measured | per-contact rule / measured |",
             "|---|---|---|---|---|---|---|---|---|---|---|",
             "| clumps on a floor | %d (%d) | %d (+%d) | [%.6g, %.6g] | %.6g | %.6f | %.4f | %.4f | %.4f | %.4f "
             "| %.4f |" % (
                 s["n_clumps"], s["n_members"], s["n_contacts"], s["n_wall_contacts"], lo, hi,
                 c["dt_critical_eigen"], c["dt_critical_eigen"] / mid, c["dt_critical_bound"] / mid,
                 gst / mid, exadem / mid, sp["dt_critical_eigen"] / mid, c["dt_contact_rule"] / mid)]
    open(os.path.join(out, "clumps_comparison.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
