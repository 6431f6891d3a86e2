"""The solver-facing call (demstep_solver_compute): a solver's own arrays, no scene."""
import math

import numpy as np
import pytest

import demstep


def test_two_spheres_closed_form():
    # two free unit masses on one normal spring k: omega_max^2 = 2 k / m, so the
    # undamped limit is 2/omega_max = sqrt(2 m / k) (dense solve: to rounding)
    x = np.array([[0.0, 0.0, 0.0], [1.9, 0.0, 0.0]])
    r = demstep.solver_critical_steps(x, np.ones(2), np.ones(2), np.array([[0, 1]]), 50.0,
                                      solver="dense")
    assert r.dt_critical_eigen == pytest.approx(math.sqrt(2.0 / 50.0), rel=1e-13)


def test_same_as_a_scene_with_its_contact_list():
    # the same particles and listed contact through a scene give the same numbers, bit for bit
    x = np.array([[0.0, 0.0, 0.0], [1.9, 0.0, 0.0], [3.8, 0.0, 0.0]])
    pairs = np.array([[0, 1], [1, 2]])
    k = np.array([[40.0, 10.0], [60.0, 20.0]])
    direct = demstep.solver_critical_steps(x, np.ones(3), np.ones(3), pairs, k[:, 0], k_t=k[:, 1],
                                           solver="dense")
    with demstep.Scene(3) as scene:
        scene.set_particles(x, np.ones(3), np.ones(3))
        scene.set_contacts(pairs, k)
        scene.set_eigen_solver("dense")
        via_scene = scene.compute()
    assert direct.dt_critical_eigen == pytest.approx(via_scene.dt_critical_eigen, rel=1e-12)


def test_a_pair_outside_is_named_with_its_index():
    x = np.array([[0.0, 0.0, 0.0], [1.9, 0.0, 0.0]])
    with pytest.raises(demstep.DemstepError) as info:
        demstep.solver_critical_steps(x, np.ones(2), np.ones(2), np.array([[0, 1], [1, 5]]), 50.0)
    err = info.value
    assert err.where == "pairs" and err.index == 1, (err.where, err.index, str(err))


def test_a_wrong_shape_is_refused_before_the_call():
    x = np.zeros((2, 3))
    with pytest.raises(demstep.DemstepError) as info:
        demstep.solver_critical_steps(x, np.ones(3), np.ones(2), np.array([[0, 1]]), 50.0)
    assert info.value.where == "mass"
