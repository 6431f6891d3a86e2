#!/usr/bin/env python3
"""Give demstep each settled LIGGGHTS scene as a user would: the dump of the
settled state, a deck with the LIGGGHTS materials in LIGGGHTS' convention
(&material code 'liggghts_hertz' or 'liggghts_hooke'), the walls, the rolling
model, Hertz linearised at the current overlaps; run the app and compare its
exact damped limit with the limit measured in LIGGGHTS (data/measured.csv).

    python3 validation/liggghts/demstep_compare.py [path/to/demstep]

Writes validation/liggghts/demstep/<scene>.dump, .nml, _result.nml and
validation/liggghts/demstep/comparison.md. Needs only python3 (no numpy)."""
import csv, json, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
data = os.path.join(here, "data")
out = os.path.join(here, "demstep")
scenes = ["a_hertz", "b_hooke", "c_epsd2", "d_periodic", "e_undamped", "f_tdoff", "g_hooke_undamped",
          "h_multisphere", "i_multisphere3", "j_multisphere_mc"]
# the peers' rules shown in the table (all nine are in each _result.nml)
peers = ["edem_rayleigh_20", "liggghts_rayleigh_10", "liggghts_hertz_10", "yade_pwave_30"]


def nominal_types(rows, radii):
    """A type per radius class (nearest nominal radius): each pair's m*, R*
    as the code takes them per contact."""
    return [1 + min(range(len(radii)), key=lambda k: abs(float(r["radius"]) - radii[k])) for r in rows]


def write_dump(scene, mat, rows, types, path):
    lo, hi = mat["box_lo"], mat["box_hi"]
    flags = "".join(("pp " if p else "ff ") for p in mat["periodic"]).strip()
    with open(path, "w") as f:
        f.write("ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n%d\n" % len(rows))
        f.write("ITEM: BOX BOUNDS %s\n" % flags)
        for a in range(3):
            f.write("%.12e %.12e\n" % (lo[a], hi[a]))
        # mol: LIGGGHTS' multisphere body of each atom (its mass column is the body's)
        mol = "mol" in rows[0]
        f.write("ITEM: ATOMS id type %sx y z vx vy vz radius mass omegax omegay omegaz\n" % ("mol " if mol else ""))
        for r, t in zip(rows, types):
            f.write("%s %d %s%s %s %s %s %s %s %s %s %s %s %s\n" % (r["id"], t, (r["mol"] + " ") if mol else "",
                    r["x"], r["y"], r["z"], r["vx"], r["vy"], r["vz"], r["radius"], r["mass"], r["omegax"],
                    r["omegay"], r["omegaz"]))


def wall_values(mat):
    vals = []
    axis = {"xplane": 0, "yplane": 1, "zplane": 2}
    for w in mat.get("walls", []):
        a = axis[w["plane"]]
        p = [0.0, 0.0, 0.0]
        n = [0.0, 0.0, 0.0]
        p[a] = w["position"]
        n[a] = float(w["inward_normal_sign"])
        vals.append(", ".join("%.12g" % v for v in p + n))
    return vals


def write_deck(scene, mat, radii, path):
    walls = wall_values(mat)
    damped = mat["coefficient_restitution"] < 1.0
    effects = ["'contacts'", "'rotation'"] + (["'walls'"] if walls else []) + (["'damping'"] if damped else [])
    lines = ["! LIGGGHTS scene %s (%s), settled; written by demstep_compare.py" % (scene, mat["description"]),
             "&scene", "  dim = 3", "  snapshot_file = '%s.dump'" % scene,
             "  hertz_linearization = 'current'", "  effects = " + ", ".join(effects)]
    if walls:
        lines.append("  walls = " + ",\n    ".join(walls))
        lines.append("  wall_type = %d" % mat["wall_type"])
    if mat["rolling_friction"] == "epsd2":
        lines.append("  rolling_ratio = 1.0")
    if not mat["tangential_damping"]:
        lines.append("  tangential_damping = F")
    if "bodies" in mat and "mass" not in mat["bodies"]:
        # the template states no mass and inertia_tensor (j): LIGGGHTS' Monte
        # Carlo gives the union's; with them (h, i: the members' sum, taken as
        # they are) demstep's default, the members' sum
        lines.append("  body_union = T")
    lines.append("/")
    code = "liggghts_hertz" if mat["model"] == "hertz" else "liggghts_hooke"
    lines += ["&material", "  code = '%s'" % code,
              "  young = %.12g, poisson = %.12g, density = %.12g" % (mat["youngs_modulus"], mat["poisson_ratio"],
                                                                  mat["density"]),
              "  radius = " + ", ".join("%.12g" % r for r in radii),
              "  restitution = %.12g" % mat["coefficient_restitution"]]
    # LIGGGHTS Hooke's stiffness takes its characteristicVelocity; for Hertz the
    # velocity only picks where the convention is evaluated (E*, G* and the
    # damping ratios do not depend on it), and the deck asks for one
    lines.append("  impact_velocity = %.12g" % (mat["characteristic_velocity"] or 1.0))
    lines.append("/")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def read_group(path, group):
    """The scalars of one result group, and its lists as lists of words."""
    text = open(path).read().replace("\n", " ")
    body = text[text.lower().index("&" + group) + len(group) + 1:]
    body = body[:body.index(" /")]
    values, key = {}, None
    for item in body.split(","):
        if "=" in item:
            key, item = item.split("=", 1)
            key = key.strip().lower()
            values[key] = []
        if key and item.strip():
            word = item.strip().strip('"').strip()
            if "*" in word and word.split("*")[0].isdigit():
                count, word = word.split("*", 1)
                values[key] += [word] * int(count)
            else:
                values[key].append(word)
    return {k: (v[0] if len(v) == 1 else v) for k, v in values.items()}


def main():
    app = sys.argv[1] if len(sys.argv) > 1 else "demstep"
    os.makedirs(out, exist_ok=True)
    measured = {r["scene"]: r for r in csv.DictReader(open(os.path.join(data, "measured.csv")))}
    # the undamped Hooke control: its limit depends on the kick (README.md); the small one
    small = {r["scene"]: r for r in csv.DictReader(open(os.path.join(data, "measured_kick1e-06.csv")))}
    measured["g_hooke_undamped"] = small["g_hooke_undamped"]
    table = []
    for scene in scenes:
        mat = json.load(open(os.path.join(data, scene, "materials.json")))
        rows = list(csv.DictReader(open(os.path.join(data, scene, "particles.csv"))))
        radii = sorted(set(mat["radii"]))
        types = nominal_types(rows, radii)
        write_dump(scene, mat, rows, types, os.path.join(out, scene + ".dump"))
        deck = os.path.join(out, scene + ".nml")
        write_deck(scene, mat, radii, deck)
        result = os.path.join(out, scene + "_result.nml")
        if os.path.exists(result):
            os.remove(result)
        run = subprocess.run([app, "-q", deck, "-o", result], capture_output=True, text=True)
        if run.returncode != 0:
            print(scene, run.stdout[-2000:], run.stderr[-2000:])
            table.append((scene, None))
            continue
        res = read_group(result, "scene_result")
        snap = read_group(result, "snapshot_result")
        res["peer"] = dict(zip(snap["peer_rules"], [float(x) for x in snap["peer_dt"]]))
        table.append((scene, res))
    with open(os.path.join(out, "comparison.md"), "w") as f:
        f.write("| scene | measured [lo, hi] s | demstep exact damped s | / measured | demstep undamped / measured "
                "| recommended / measured | " + " | ".join(peers) + " |\n")
        f.write("|---|---|---|---|---|---|" + "---|" * len(peers) + "\n")
        for scene, res in table:
            m = measured.get(scene)
            if m is None:
                continue
            lo, hi = float(m["dt_measured_lo"]), float(m["dt_measured_hi"])
            mid = 0.5 * (lo + hi)
            if res is None:
                f.write("| %s | [%.5g, %.5g] | refused | | | |\n" % (scene, lo, hi))
                continue
            dd = float(res["dt_critical_damped"])
            du = float(res["dt_critical_eigen"])
            dr = float(res["dt_recommended"])
            f.write("| %s | [%.5g, %.5g] | %.5g | %.4f | %.4f | %.4f | " % (scene, lo, hi, dd, dd / mid, du / mid,
                                                                       dr / mid)
                    + " | ".join("%.3f" % (res["peer"][p] / mid) for p in peers) + " |\n")
    print(open(os.path.join(out, "comparison.md")).read())


if __name__ == "__main__":
    main()
