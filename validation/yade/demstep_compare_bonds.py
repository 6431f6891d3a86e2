#!/usr/bin/env python3
"""Give demstep the cemented Yade samples (data/bonded and data/bonded_poly,
yade_bonds.py [--poly]) as a user
would: the exported spheres as a particle table, the bonds as a bonds table and
Yade's own material inputs (young, poisson, alphaKr, alphaKtw) as the 'yade'
bond model, from which demstep makes each bond's normal, shear, bending and
twisting springs. Runs the app with the material's alphas and with both set to
0 (bending and twisting left out) and compares with the limit measured in Yade.

    python3 validation/yade/demstep_compare_bonds.py [path/to/demstep]

Writes validation/yade/demstep/bonded*.nml, bonded*_result.nml and
results_bonds.md. Needs only python3."""
import json, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "demstep")


def scalar(path, key):
    text = open(path).read()
    k = text.upper().index(key.upper() + "=")
    return float(text[k + len(key) + 1:].split(",")[0])


def deck(case, name, s, alpha_kr, alpha_ktw):
    path = os.path.join(out, name + ".nml")
    with open(path, "w") as f:
        f.write("! Yade cemented sample '%s' (yade_bonds.py); written by demstep_compare_bonds.py\n" % case)
        f.write("&scene\n  dim = 3\n  particles_file = '../data/%s/particles.txt'\n" % case)
        f.write("  bonds_file = '../data/%s/bonds.txt'\n" % case)
        f.write("  bond_model = 'yade'   ! Yade's CohFrictMat inputs: young, poisson (ks/kn), alphaKr, alphaKtw\n")
        f.write("  bond_parameters = %r, %r, %r, %r\n" % (s["young"], s["poisson_ks_over_kn"], alpha_kr, alpha_ktw))
        f.write("  effects = 'rotation'\n  eigen_solver = 'dense'\n/\n")
    return path


def table(app, case):
    s = json.load(open(os.path.join(here, "data", case, "summary.json")))
    lo, hi = s["measured_dt_lo"], s["measured_dt_hi"]
    mid = 0.5 * (lo + hi)
    values = {}
    for name, alphas in ((case, (s["alpha_kr"], s["alpha_ktw"])), (case + "_no_moments", (0.0, 0.0))):
        result = os.path.join(out, name + "_result.nml")
        run = subprocess.run([app, "-q", deck(case, name, s, *alphas), "-o", result], capture_output=True,
                             text=True)
        if run.returncode != 0:
            sys.exit(name + ": " + run.stdout[-1000:] + run.stderr[-1000:])
        values[name] = {k: scalar(result, k) for k in ("dt_critical_eigen", "dt_critical_bound", "dt_contact_rule")}
    v = values[case]
    rows = [
        ("measured in Yade (bisection on kinetic-energy growth)", "[%.7g, %.7g]" % (lo, hi), ""),
        ("demstep exact, 'yade' bonds (normal, shear, bending, twisting)", "%.7g" % v["dt_critical_eigen"],
         "%.5f" % (v["dt_critical_eigen"] / mid)),
        ("demstep exact, bending and twisting left out (alphas 0)",
         "%.7g" % values[case + "_no_moments"]["dt_critical_eigen"],
         "%.4f" % (values[case + "_no_moments"]["dt_critical_eigen"] / mid)),
        ("demstep Gershgorin bound (safe)", "%.7g" % v["dt_critical_bound"], "%.4f" % (v["dt_critical_bound"] / mid)),
        ("per-bond rule min 2 sqrt(m*/max(k_n, k_t)) (unsafe)", "%.7g" % v["dt_contact_rule"],
         "%.4f" % (v["dt_contact_rule"] / mid)),
        ("Yade PWaveTimeStep", "%.7g" % s["PWaveTimeStep"], "%.4f" % (s["PWaveTimeStep"] / mid)),
        ("Yade GlobalStiffnessTimeStepper (raw)", "%.3g (its defaultDt)" % s["GlobalStiffnessTimeStepper_raw"],
         "no estimate"),
    ]
    lines = ["`%s`: %d spheres (radii %.4g to %.4g m, jittered fcc), %d CohFrictPhys bonds "
             "(penetration %.3g to %.3g m: gaps and overlaps), young %g, poisson %g, alphaKr %g, alphaKtw %g; "
             "Yade %s." % (case, s["n_particles"], s["radius_min"], s["radius_max"], s["n_bonds"],
                           s["penetration_min"], s["penetration_max"], s["young"], s["poisson_ks_over_kn"],
                           s["alpha_kr"], s["alpha_ktw"], s["yade_version"]),
             "",
             "| estimate | dt (s) | / measured midpoint |", "|---|---|---|"]
    lines += ["| %s | %s | %s |" % r for r in rows]
    return lines


def main():
    app = sys.argv[1] if len(sys.argv) > 1 else "demstep"
    os.makedirs(out, exist_ok=True)
    lines = []
    for case in ("bonded", "bonded_poly"):
        if lines:
            lines.append("")
        lines += table(app, case)
    open(os.path.join(here, "results_bonds.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
