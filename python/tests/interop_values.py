"""The numbers of interop/c/demstep_example.c (and example/capi_reference.f90),
computed through the Python package: the same calls with the same arguments."""
import numpy as np

import demstep


def values():
    """name -> value, the names the C and Fortran programs print."""
    out = {}
    spring = demstep.Spring(0.01, 1.0e5, 0.0, compression_only=True, dashpot="lagged")
    dt_crit = spring.critical_time_step()
    out["dt_critical"] = dt_crit
    state = demstep.SpringState(x=0.0, v=1.0, step=0)
    for _ in range(1000):
        state = spring.step(0.1 * dt_crit, state)
    out["x_1000"] = state.x
    out["v_1000"] = state.v
    out["e_half_period"] = demstep.harmonic_error(19.316, 0.9, 9.658)
    out["e_hard"] = demstep.harmonic_error(1000.0, 1.0 - 1.0e-9, 1.0e7 + 1.0)
    r = demstep.n_roots(0.9, 1.0e-3, "fraction", 0.5, "largest_step")
    out["n_pick"] = r.n_pick
    out["n_zero"] = r.n_zero
    # the C program's lambdas: 0.9 + (0.99 - 0.9) * i / 9.0, evaluated as C does
    lambdas = [0.9 + (0.99 - 0.9) * i / 9.0 for i in range(10)]
    res = demstep.simulated_stiffness(0.01, 1.0e5, 1.0e-3, lambdas)
    for name in ("n_star", "lambda_star", "dt", "stiffness_actual"):
        out[name] = getattr(res, name)
    with demstep.Scene(1) as chain:
        fixed = np.zeros(12, dtype=bool)
        fixed[[0, 11]] = True
        chain.set_particles(np.arange(1.0, 13.0), np.ones(12), np.full(12, 0.3), fixed=fixed)
        chain.add_bonds([(i, i + 1) for i in range(11)])
        chain.set_bond_stiffness(100.0, 0.0)
        chain.set_effects(0)
        c = chain.compute()
    out["omega_max"] = c.omega_max
    out["dt_critical_bound"] = c.dt_critical_bound
    out["dt_contact_rule"] = c.dt_contact_rule
    with demstep.Scene(2) as wall:
        wall.set_particles([[0.0, 0.0099]], [0.01], [0.01])
        wall.add_walls([[0.0, 0.0]], [[0.0, 1.0]])
        wall.set_contact_law("hertz", 1.0e8, 4.0e7)
        wall.set_damping(0.1)
        wall.set_effects({"walls", "damping"})
        c = wall.compute("impact", 2.0)
    out["wall_omega_max"] = c.omega_max
    out["wall_dt_critical_damped"] = c.dt_critical_damped
    with demstep.Scene(3) as clump:
        clump.set_particles([[0.3, -0.2, 1.2], [0.9, 0.2, 1.8]], [1.0, 1.5], [1.0, 1.0])
        clump.add_walls([[0.0, 0.0, 0.201]], [[0.0, 0.0, 1.0]])
        clump.set_contact_law("linear", 1.0e4, 0.0)
        clump.set_effects({"contacts", "walls", "rotation"})
        clump.set_bodies([1, 1])
        c = clump.compute()
        gst, exadem = clump.body_peer_steps()
    out["clump_omega_max"] = c.omega_max
    out["clump_dt_critical_eigen"] = c.dt_critical_eigen
    out["clump_yade_gst"] = gst
    out["clump_exadem"] = exadem
    with demstep.Scene(3) as pair:
        pair.set_particles([[0.0, 0.0, 0.0], [1.2, 1.1, 0.9]], [1.0, 1.5], [1.0, 0.9])
        pair.add_bonds([(0, 1)])
        pair.set_bond_model("yade", [1.0e5, 0.3, 2.0, 2.0])
        c = pair.compute()
    out["bond_omega_max"] = c.omega_max
    out["bond_dt_critical_eigen"] = c.dt_critical_eigen
    out["contact_restitution"] = demstep.contact_with_onset(20.0, 0.5, 0.1).restitution
    out["n_for_tolerance"] = demstep.n_for_tolerance("restitution", 1.0e-3, 0.0, 0.0)
    # a solver's own arrays: three spheres in a row (1D), the middle one light
    c, shares, contact_shares, _ = demstep.solver_participation(
        [[0.0], [1.9e-3], [3.8e-3]], [1.0e-3, 2.0e-4, 1.0e-3], [1.0e-3, 1.0e-3, 1.0e-3], [(0, 1), (1, 2)], 1.0e4)
    out["solver_dt_critical_eigen"] = c.dt_critical_eigen
    out["solver_share_1"] = shares[0]
    out["solver_share_2"] = shares[1]
    out["solver_contact_share_1"] = contact_shares[0]
    return out


def read(text):
    """The "name value" lines of the C and Fortran programs (bad_* lines are statuses)."""
    found = {}
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 2 and not parts[0].startswith("bad_"):
            found[parts[0]] = float(parts[1])
    return found
