"""The Python path against the Fortran and C paths: the same numbers bit for bit.

As .ci/interop compares the C, C++ and Fortran programs of interop/ ("name value"
lines, every double equal), this compares the package's numbers with
- the Fortran reference example/capi_reference.f90 (run by fpm, when fpm is on the PATH),
- the C program interop/c/demstep_example.c linked to the package's own library
  (when a C compiler is on the PATH),
- the demstep app bundled with the package, on a Yade and a LIGGGHTS validation scene.
No tolerance: the same library computes every number, so any difference is a
marshalling error (a wrong argument, order or conversion).
"""
import shutil
import subprocess

import numpy as np
import pytest

import demstep
from interop_values import read, values


def test_python_equals_fortran_reference(root):
    if shutil.which("fpm") is None:
        pytest.skip("fpm is not on the PATH: no Fortran reference")
    done = subprocess.run(["fpm", "run", "--example", "capi_reference"], cwd=root, capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    fortran = read(done.stdout)
    python = values()
    assert len(fortran) == 28 and fortran.keys() == python.keys()
    assert {k: v for k, v in python.items() if v != fortran[k]} == {}


def test_python_equals_c_on_the_same_library(root, tmp_path):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler on the PATH")
    lib = demstep.library_path()
    exe = tmp_path / "demstep_c"
    subprocess.run([cc, "-std=c99", "-I", str(root / "include"), str(root / "interop/c/demstep_example.c"),
                    str(lib), f"-Wl,-rpath,{lib.parent}", "-lm", "-o", str(exe)], check=True)
    c = read(subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout)
    python = values()
    assert len(c) == 28 and c.keys() == python.keys()
    assert {k: v for k, v in python.items() if v != c[k]} == {}


def _yade_sc_scene(root):
    """validation/yade/data/sc as example/yade_sc.nml gives it to the app."""
    data = root / "validation/yade/data/sc"
    p = np.loadtxt(data / "particles.txt")
    contacts = np.loadtxt(data / "contacts.txt")
    scene = demstep.Scene(3)
    scene.set_particles(p[:, 0:3], p[:, 6], p[:, 7], fixed=p[:, 8].astype(int), inertia=p[:, 9],
                        velocity=p[:, 3:6])
    scene.set_contacts(contacts[:, :2].astype(int) - 1, contacts[:, 2:4])
    scene.set_cell([1, 1, 1], [0.0, 0.0, 0.0], [0.11988000000000001] * 3)
    scene.set_effects({"contacts", "rotation"})
    return scene


def test_yade_sc_scene_equals_the_app(root, run_app):
    app = run_app(root / "example/yade_sc.nml")
    with _yade_sc_scene(root) as scene:
        c = scene.compute()
    assert c.n_dof == app["n_dof"] == 1296
    for name in ("omega_max", "dt_critical_eigen", "dt_critical_bound", "dt_critical_safe",
                 "dt_critical_damped", "dt_contact_rule"):
        assert getattr(c, name) == app[name], name


def test_liggghts_hertz_scene_equals_the_app(root, run_app):
    """validation/liggghts a_hertz: a LIGGGHTS dump, materials in LIGGGHTS' Hertz
    convention (dashpots of e = 0.5), six walls of type 1 (0 here), damping on."""
    deck = root / "validation/liggghts/demstep/a_hertz.nml"
    app = run_app(deck)
    rows = np.loadtxt(deck.parent / "a_hertz.dump", skiprows=9)  # id type x y z vx vy vz radius mass ...
    walls = np.array([[-0.01, 0, 0, 1, 0, 0], [0.01, 0, 0, -1, 0, 0], [0, -0.01, 0, 0, 1, 0],
                      [0, 0.01, 0, 0, -1, 0], [0, 0, 0, 0, 0, 1], [0, 0, 0.05, 0, 0, -1]], dtype=float)
    with demstep.Scene(3) as scene:
        scene.set_particles(rows[:, 2:5], rows[:, 9], rows[:, 8], velocity=rows[:, 5:8])
        scene.set_materials(rows[:, 1].astype(int) - 1, [1.0e7] * 3, [0.3] * 3, [2500.0] * 3,
                            [0.001, 0.00125, 0.0015], "liggghts_hertz", 0.5, 1.0, wall_type=0)
        scene.add_walls(walls[:, :3], walls[:, 3:])
        scene.set_effects(["contacts", "rotation", "walls", "damping"])
        c = scene.compute("current")
    assert c.n_dof == app["n_dof"] == 729 * 6
    for name in ("omega_max", "dt_critical_eigen", "dt_critical_bound", "dt_critical_damped",
                 "dt_critical_damped_bound"):
        assert getattr(c, name) == app[name], name


def test_liggghts_scene_through_read_snapshot_equals_the_app(root, run_app):
    """The same a_hertz scene with its dump read by the library's snapshot reader
    (demstep_snapshot_read), as the app reads the deck's snapshot_file."""
    deck = root / "validation/liggghts/demstep/a_hertz.nml"
    app = run_app(deck)
    snap = demstep.read_snapshot(deck.parent / "a_hertz.dump")
    assert snap.n == 729 and snap.has_mass and snap.has_velocity and not snap.periodic.any()
    walls = np.array([[-0.01, 0, 0, 1, 0, 0], [0.01, 0, 0, -1, 0, 0], [0, -0.01, 0, 0, 1, 0],
                      [0, 0.01, 0, 0, -1, 0], [0, 0, 0, 0, 0, 1], [0, 0, 0.05, 0, 0, -1]], dtype=float)
    with demstep.Scene(3) as scene:
        scene.set_particles(snap.x, snap.mass, snap.radius, velocity=snap.v)
        scene.set_materials(snap.type, [1.0e7] * 3, [0.3] * 3, [2500.0] * 3, [0.001, 0.00125, 0.0015],
                            "liggghts_hertz", 0.5, 1.0, wall_type=0)
        scene.add_walls(walls[:, :3], walls[:, 3:])
        scene.set_effects(["contacts", "rotation", "walls", "damping"])
        c = scene.compute("current")
    for name in ("omega_max", "dt_critical_eigen", "dt_critical_bound", "dt_critical_damped"):
        assert getattr(c, name) == app[name], name


def test_materials_and_peer_rules_equal_the_app(root, run_app):
    """example/material.nml (glass, 0.5 and 1 mm radii, e = 0.9, 1 m/s, code 'all'):
    each pair's contact in every convention and each peer's rule, as the app's
    &material_result (conventions fastest, then pairs 1-1, 1-2, 2-2)."""
    app = run_app(root / "example/material.nml", arrays=True)
    glass = [demstep.Material(6.3e10, 0.22, 2500.0, r) for r in (0.5e-3, 1.0e-3)]
    conventions = [name[len("DEMSTEP_CODE_"):].lower() for name, _ in
                   sorted((n, v) for n, v in demstep.CONSTANTS.items() if n.startswith("DEMSTEP_CODE_"))]
    conventions.sort(key=lambda c: demstep.CONSTANTS["DEMSTEP_CODE_" + c.upper()])
    pairs = list(zip(app["type_i"], app["type_j"]))
    assert pairs == [(1, 1), (1, 2), (2, 2)] and len(app["dt_code"]) == 9 * 3
    for p, (i, j) in enumerate(pairs):
        a, b = glass[int(i) - 1], glass[int(j) - 1]
        for c, code in enumerate(conventions):
            got = demstep.contact_parameters(a, b, code, 0.9, 1.0)
            for field in ("k_n", "k_t", "gamma_n", "gamma_t", "dt_code"):
                assert getattr(got, field) == app[field][9 * p + c], (pairs[p], code, field)
        assert got.m_star == app["m_star"][p]
        peers = demstep.peer_time_steps(a, b, 0.9, 1.0)
        assert list(peers.dt.values()) == app["peer_dt"][9 * p:9 * p + 9]
        assert peers.rayleigh == app["rayleigh_time"][p] and peers.hertz_duration == app["hertz_duration"][p]
