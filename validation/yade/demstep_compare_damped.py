#!/usr/bin/env python3
"""Give demstep the two damped Yade piles (data/viscel, data/cohfrict) as a
user would: the exported spheres as a particle table and every interaction,
with its own kn, ks, kr, ktw, cn, cs, as an explicit contact list; a sphere on
a fixed facet becomes a contact with a fixed point-like partner (radius 1e-6
of the sphere's) on the facet's far side, so that the contact has the
interaction's normal, overlap and contact point (the sphere's lever arm
r - delta/2, as Yade's facet geometry). Runs the app and compares its exact
damped limit with the limit measured in Yade and with reference_damped.py.

    python3 validation/yade/demstep_compare_damped.py [path/to/demstep]

Writes validation/yade/demstep/<scene>_particles.txt, _contacts.txt, .nml,
_result.nml and comparison.md. Needs only python3."""
import csv, json, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "demstep")
scenes = {"viscel": "per_sphere", "cohfrict": "total"}


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def convert(scene):
    parts = rows(os.path.join(here, "data", scene, "particles.csv"))
    inter = rows(os.path.join(here, "data", scene, "interactions.csv"))
    table = []
    for p in parts:
        table.append([float(p[k]) for k in ("x", "y", "z")] + [0.0, 0.0, 0.0] +
                     [float(p["mass"]), float(p["radius"]), int(p["fixed"]), float(p["inertia"])])
    contacts = []
    for c in inter:
        n = [float(c[k]) for k in ("nx", "ny", "nz")]
        k = [float(c[x]) for x in ("kn", "ks", "kr", "ktw", "cn", "cs")] + [0.0, 0.0]
        d = float(c["overlap"])
        if c["kind1"] == "p" and c["kind2"] == "p":
            contacts.append([int(c["i1"]) + 1, int(c["i2"]) + 1] + k)
            continue
        # a facet (body 1) and a sphere (body 2); n from the facet to the sphere
        s = int(c["i2"])
        x = table[s][:3]
        r = table[s][7]
        rg = 1.0e-6 * r
        g = [x[a] - (r + rg - d) * n[a] for a in range(3)]
        table.append(g + [0.0, 0.0, 0.0, 1.0, rg, 1, 0.4 * rg * rg])
        contacts.append([len(table), s + 1] + k)
    with open(os.path.join(out, scene + "_particles.txt"), "w") as f:
        f.write("# x y z vx vy vz m r fixed I (the spheres, then the facet contacts' fixed partners)\n")
        for t in table:
            f.write("%.17g %.17g %.17g %g %g %g %.17g %.17g %d %.17g\n" % tuple(t))
    with open(os.path.join(out, scene + "_contacts.txt"), "w") as f:
        f.write("# i j k_n k_t k_r k_w c_n c_t c_r c_w (Yade's own values per interaction)\n")
        for c in contacts:
            f.write("%d %d %.17g %.17g %.17g %.17g %.17g %.17g %g %g\n" % tuple(c))
    with open(os.path.join(out, scene + ".nml"), "w") as f:
        f.write("! Yade pile '%s', settled; written by demstep_compare_damped.py\n" % scene)
        f.write("&scene\n  dim = 3\n  particles_file = '%s_particles.txt'\n" % scene)
        f.write("  contacts_file = '%s_contacts.txt'\n" % scene)
        f.write("  effects = 'contacts', 'rotation', 'damping'\n")
        f.write("  damping_ratio = 0.0   ! the listed dashpots are the contacts' own\n/\n")


def scalar(path, key):
    text = open(path).read()
    k = text.upper().index(key.upper() + "=")
    return float(text[k + len(key) + 1:].split(",")[0])


def main():
    app = sys.argv[1] if len(sys.argv) > 1 else "demstep"
    os.makedirs(out, exist_ok=True)
    lines = ["| scene | Yade criterion | measured [lo, hi] s | demstep exact damped s | / measured "
             "| reference_damped.py s | demstep / reference | demstep undamped / measured |",
             "|---|---|---|---|---|---|---|---|"]
    for scene, criterion in scenes.items():
        convert(scene)
        result = os.path.join(out, scene + "_result.nml")
        run = subprocess.run([app, "-q", os.path.join(out, scene + ".nml"), "-o", result],
                             capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(scene + ": " + run.stdout[-1000:] + run.stderr[-1000:])
        ref = json.load(open(os.path.join(here, "data", scene, "reference.json")))
        m = [x for x in ref["measured"] if x["criterion"] == criterion and x["v0"] == 1e-7][0]
        mid = 0.5 * (m["lo"] + m["hi"])
        dd = scalar(result, "dt_critical_damped")
        du = scalar(result, "dt_critical_safe")
        model = ref["yade"]["damped_limit"]
        lines.append("| %s | %s, V0 1e-7 | [%.6g, %.6g] | %.6g | %.4f | %.6g | %.6f | %.4f |" % (
            scene, criterion.replace("_", "-"), m["lo"], m["hi"], dd, dd / mid, model, dd / model, du / mid))
    open(os.path.join(out, "comparison.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
