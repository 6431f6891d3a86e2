"""demstep.yade: a scene from Yade's O.

With Yade on the PATH (Debian's `yade`), the "sc" assembly of validation/yade is
built in Yade and demstep.yade reads O; its limit is checked against the same
assembly from the committed export (validation/yade/data/sc, through demstep)
and against Yade's measured largest stable step. Without Yade, that test is
skipped; the conversion itself is tested on a fake O with Yade's attribute names.
"""
import json
import math
import shutil
import subprocess
import types
from pathlib import Path

import numpy as np
import pytest

import demstep
import demstep.yade


def ns(**kw):
    return types.SimpleNamespace(**kw)


class Sphere:
    def __init__(self, radius):
        self.radius = radius


class Facet:
    pass


def body(id, pos, radius=None, mass=1.0, dynamic=True, blocked=""):
    shape = Sphere(radius) if radius is not None else Facet()
    inertia = 0.4 * mass * (radius or 0.0) ** 2
    return ns(id=id, shape=shape, dynamic=dynamic, isClump=False, isClumpMember=False,
              state=ns(pos=np.array(pos, float), mass=mass, inertia=np.array([inertia] * 3),
                       vel=np.zeros(3), blockedDOFs=blocked))


def interaction(id1, id2, kn, ks, normal, depth=0.0, **extra):
    return ns(isReal=True, id1=id1, id2=id2, phys=ns(kn=kn, ks=ks, **extra),
              geom=ns(normal=np.array(normal, float), penetrationDepth=depth, contactPoint=np.zeros(3)))


def fake_o(bodies, interactions, cell=None):
    o = ns(bodies=bodies, interactions=interactions, periodic=cell is not None)
    if cell is not None:
        o.cell = ns(hSize=np.diag(cell))
    return o


def test_pair_equals_the_scene_built_by_hand():
    """Two spheres: the same numbers as the explicit contact list given directly."""
    o = fake_o([body(0, [0, 0, 0], 0.01, 0.01), body(1, [0.0199, 0, 0], 0.01, 0.01), body(2, [5, 5, 5])],
               [interaction(0, 1, 1.0e5, 3.0e4, [1, 0, 0], 1.0e-4), ns(isReal=False)])
    scene, ids = demstep.yade.read(o)
    assert ids == [0, 1]
    with scene:
        got = scene.compute()
    with demstep.Scene(3) as s:
        s.set_particles([[0, 0, 0], [0.0199, 0, 0]], [0.01] * 2, [0.01] * 2, inertia=[0.4e-6] * 2)
        s.set_contacts([[0, 1]], [[1.0e5, 3.0e4]])
        s.set_effects({"contacts", "rotation"})
        want = s.compute()
    assert got == want
    # the top mode of two free equal spheres: translation 2 k_n/m, or the rolling one
    assert got.n_dof == 12 and got.rotation == 1


def test_wall_contact_is_a_fixed_twin():
    """A sphere on a facet below it (facet id1, normal up): one contact with a fixed
    twin; its translational mode is sqrt(k_n / m) exactly (a spring to the ground)."""
    o = fake_o([body(7, [0, 0, 0]), body(3, [0, 0, 0.0099], 0.01, 0.01)],
               [interaction(7, 3, 2.0e5, 0.0, [0, 0, 1], 1.0e-4)])
    scene, ids = demstep.yade.read(o)
    assert ids == [3, 3]
    with scene:
        c = scene.compute()
    assert c.n_dof == 6 and c.n_springs == 1
    assert c.omega_max == pytest.approx(math.sqrt(2.0e5 / 0.01), rel=1e-14)


def test_periodic_cell_and_nearest_image():
    size = 0.1
    o = fake_o([body(0, [0.001, 0.05, 0.05], 0.01, 0.01), body(1, [0.0999, 0.05, 0.05], 0.01, 0.01)],
               [interaction(0, 1, 1.0e5, 0.0, [-1, 0, 0], 1.71e-2)], cell=[size] * 3)
    scene, _ = demstep.yade.read(o)
    with scene:
        c = scene.compute()
    assert c.periodic == 1
    assert c.omega_max == pytest.approx(math.sqrt(2 * 1.0e5 / 0.01), rel=1e-12)
    # Yade's normal pointing the other way: not the nearest image, refused
    o.interactions[0].geom.normal = np.array([1.0, 0, 0])
    with pytest.raises(demstep.DemstepError) as info:
        demstep.yade.read(o)
    assert info.value.where == "O.interactions" and "nearest periodic image" in info.value.message


def test_refusals_and_warnings():
    o = fake_o([body(0, [0, 0, 0], 0.01, blocked="xyz")], [])
    with pytest.raises(demstep.DemstepError) as info:
        demstep.yade.read(o)
    assert (info.value.where, info.value.index) == ("O.bodies", 0) and "blockedDOFs 'xyz'" in info.value.message
    o = fake_o([body(0, [0, 0, 0], 0.01)], [], cell=[0.1] * 3)
    o.cell.hSize = np.array([[0.1, 0.01, 0], [0, 0.1, 0], [0, 0, 0.1]])
    with pytest.raises(demstep.DemstepError) as info:
        demstep.yade.read(o)
    assert info.value.where == "O.cell.hSize"
    o = fake_o([body(0, [0, 0, 0], 0.01), body(1, [0.0199, 0, 0], 0.01)],
               [interaction(0, 1, 1.0e5, 3.0e4, [1, 0, 0], 1.0e-4, cn=0.5, cs=0.1)])
    with pytest.warns(UserWarning, match="undamped limit"):
        scene, _ = demstep.yade.read(o)
    scene.free()


def test_yade_sc_assembly(root, tmp_path):
    yade = shutil.which("yade")
    if yade is None:
        pytest.skip("Yade is not installed (Debian: apt-get install yade)")
    # only the package on Yade's path (Yade keeps Debian's numpy)
    link = tmp_path / "path"
    link.mkdir()
    (link / "demstep").symlink_to(Path(demstep.__file__).parent)
    out = tmp_path / "yade.json"
    done = subprocess.run([yade, "-n", "-j1", "-x", str(Path(__file__).with_name("yade_sc_check.py")), str(out)],
                          env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(link), "HOME": str(tmp_path)},
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and out.is_file(), done.stdout[-2000:] + done.stderr[-2000:]
    got = json.loads(out.read_text())
    assert got["n_bodies"] == 216 and got["n_interactions"] == 648
    r = got["result"]
    assert (r["n_dof"], r["n_springs"], r["periodic"], r["rotation"]) == (1296, 648, 1, 1)
    # the committed export of the same assembly, through demstep: the same limit
    # up to rounding (Yade's kn = E R is 1e5 within an ulp or so; contact order differs)
    data = root / "validation/yade/data/sc"
    p = np.loadtxt(data / "particles.txt")
    contacts = np.loadtxt(data / "contacts.txt")
    with demstep.Scene(3) as scene:
        scene.set_particles(p[:, 0:3], p[:, 6], p[:, 7], inertia=p[:, 9])
        scene.set_contacts(contacts[:, :2].astype(int) - 1, contacts[:, 2:4])
        scene.set_cell([1, 1, 1], [0.0] * 3, json.loads((data / "cell.json").read_text())["cell_hi"])
        scene.set_effects({"contacts", "rotation"})
        export = scene.compute()
    assert r["dt_critical_eigen"] == pytest.approx(export.dt_critical_eigen, rel=1e-12)
    # and Yade's measured largest stable step: demstep's symmetric model is 0.9995
    # of it (validation/yade/README.md); below the bracket, within 0.1 %
    summary = json.loads((data / "summary.json").read_text())
    assert 0.999 * summary["measured_dt_lo"] < r["dt_critical_eigen"] < summary["measured_dt_lo"]
