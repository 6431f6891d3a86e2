"""Bad arrays and values: one exception type, DemstepError, naming the argument.

Shapes and dtypes are checked by the package before the call (the C API cannot
see them) and reported in the library's form, "function: argument: what", with
`where` the C parameter's name; values (NaN, signs, ranges) go to the library,
which refuses them with its own message and status.
"""
import ctypes

import numpy as np
import pytest

import demstep
from demstep import _capi
from demstep._errors import check

INVALID = demstep.CONSTANTS["DEMSTEP_INVALID_INPUT"]


def raised(call):
    with pytest.raises(demstep.DemstepError) as info:
        call()
    return info.value


def scene3(n=2):
    scene = demstep.Scene(3)
    x = np.zeros((n, 3))
    x[:, 0] = 1.9 * np.arange(n)
    scene.set_particles(x, np.ones(n), np.ones(n))
    return scene


@pytest.mark.parametrize("argument, bad, what", [
    ("x", np.zeros((2, 2)), "must have shape (n, 3) (dim coordinates per particle), got (2, 2)"),
    ("x", np.zeros(6), "must have shape (n, 3)"),
    ("mass", np.ones(3), "must have shape (2,) (one per particle), got (3,)"),
    ("radius", np.ones((2, 1)), "must have shape (2,)"),
    ("velocity", np.zeros((2, 2)), "must have shape (2, 3)"),
    ("fixed", np.zeros(1, dtype=bool), "must have shape (2,)"),
    ("mass", np.array(["1", "2"]), "must hold real numbers, got dtype <U1"),
    ("radius", np.ones(2, dtype=complex), "must hold real numbers, got dtype complex128"),
    ("fixed", np.array([0.0, 1.0]), "must hold booleans or integers, got dtype float64"),
])
def test_particle_arrays_of_wrong_shape_or_dtype(argument, bad, what):
    arrays = {"x": np.zeros((2, 3)), "mass": np.ones(2), "radius": np.ones(2)}
    arrays[argument] = bad
    with demstep.Scene(3) as scene:
        e = raised(lambda: scene.set_particles(**arrays))
        assert e.code == INVALID and e.code_name == "DEMSTEP_INVALID_INPUT"
        assert e.where == argument and e.index is None
        assert e.function == "demstep_scene_set_particles"
        assert e.message.startswith(f"demstep_scene_set_particles: {argument}: ")
        assert what in e.message
        # refused before the call: the scene is still usable
        scene.set_particles(np.zeros((1, 3)), [1.0], [1.0])


def test_contact_arrays():
    with scene3() as scene:
        e = raised(lambda: scene.set_contacts([[0, 1]], [[1.0e5, 0.0, 0.0]]))
        assert (e.where, e.index) == ("k", None) and "got (1, 3)" in e.message
        e = raised(lambda: scene.set_contacts([[0.0, 1.0]], [[1.0e5, 0.0]]))
        assert e.where == "pairs" and "integers, got dtype float64" in e.message
        e = raised(lambda: scene.set_contacts([[0, 1], [0, 2**40]], [[1.0e5, 0.0]] * 2))
        assert (e.where, e.index) == ("pairs", 3) and "beyond a C int" in e.message
        scene.set_contacts([[0, 1]], [[1.0e5, 0.0]])
        assert scene.compute().n_springs == 1


def test_other_arrays_name_their_argument():
    cases = [
        (lambda s: s.add_walls([[0.0, 0.0, 0.0]], [[0.0, 1.0]]), "normals"),
        (lambda s: s.set_cell([1, 1], [0.0] * 3, [1.0] * 3), "periodic"),
        (lambda s: s.set_cell([1, 1, 1], [0.0] * 3, [1.0] * 2), "hi"),
        (lambda s: s.set_gravity([0.0, -9.81]), "gravity"),
        (lambda s: s.set_types([0, 0], np.ones((2, 3))), "k_normal"),
        (lambda s: s.set_types([0, 0, 0], np.ones((1, 1))), "types"),
        (lambda s: s.set_hertz_types([0, 0], [1.0e7], [0.3, 0.3]), "poisson"),
        (lambda s: s.set_materials([0, 0], [1.0e7], [0.3], [2500.0, 1.0], [0.001], "liggghts_hertz",
                                   0.5, 1.0), "density"),
        (lambda s: s.add_bonds([0, 1]), "bonds"),
    ]
    for call, argument in cases:
        with scene3() as scene:
            e = raised(lambda: call(scene))
            assert e.code == INVALID and e.where == argument, (argument, e.message)
    e = raised(lambda: demstep.simulated_stiffness(0.01, 1.0e5, 1.0e-3, [[0.9, 0.95]]))
    assert e.where == "lambdas"
    e = raised(lambda: demstep.simulated_stiffness(0.01, 1.0e5, 1.0e-3, [0.9, 0.95], weights=[1.0]))
    assert e.where == "weights"


def test_names_of_enum_values():
    with scene3() as scene:
        e = raised(lambda: scene.set_contact_law("quadratic", 1.0))
        assert e.where == "law" and "'linear', 'hertz'" in e.message
        e = raised(lambda: scene.set_effects({"contacts", "magnetism"}))
        assert e.where == "effects" and "'local_damping'" in e.message
        e = raised(lambda: scene.compute("sometimes"))
        assert e.where == "hertz_linearization"
    e = raised(lambda: demstep.Spring(1.0, 1.0, dashpot="forward"))
    assert e.where == "dashpot" and "'lagged', 'centred'" in e.message


def test_nan_goes_to_the_library():
    # the library refuses NaN with its own message: the argument and the particle
    with demstep.Scene(3) as scene:
        x = np.zeros((2, 3))
        x[1, 2] = np.nan
        e = raised(lambda: scene.set_particles(x, np.ones(2), np.ones(2)))
        assert e.code == INVALID
        assert e.message == "demstep_scene_set_particles: position: particle 2 is not finite"
        # a failed builder call leaves the scene unusable (the C API's rule), quoted
        e = raised(lambda: scene.set_contact_law("linear", 1.0e5))
        assert "unusable since a call failed (demstep_scene_set_particles: position" in e.message
    with scene3() as scene:
        e = raised(lambda: scene.set_contacts([[0, 1]], [[np.nan, 0.0]]))
        assert e.message == "demstep_scene_set_contacts: contacts(1): k_n must be > 0 and finite"
    with scene3() as scene:
        e = raised(lambda: scene.set_gravity([0.0, 0.0, np.nan]))
        assert "gravity: needs 3 finite components" in e.message
    e = raised(lambda: demstep.simulated_stiffness(0.01, 1.0e5, 1.0e-3, [0.9, np.nan]))
    assert e.message == "demstep_simulated_stiffness: lambda: element 2 is NaN; must be in (0, 1)"
    e = raised(lambda: demstep.harmonic_error(np.nan, 0.9, 5.0))
    assert e.code == INVALID and e.message.startswith("demstep_harmonic_error: ")
    e = raised(lambda: demstep.Spring(0.01, 1.0e5).step(np.nan, demstep.SpringState(0.0, 1.0, 0)))
    assert e.message == "demstep_spring_step: dt must be finite and > 0"
    with scene3() as scene:
        e = raised(lambda: scene.set_damping(np.nan))
        assert e.code == INVALID and e.function == "demstep_scene_set_damping"


def test_other_statuses_keep_their_code():
    e = raised(lambda: demstep.n_for_tolerance("restitution", 1.0e-9, 0.0, 30.0))
    assert e.code == demstep.CONSTANTS["DEMSTEP_NOT_FOUND"] == 5
    assert e.code_name == "DEMSTEP_NOT_FOUND" and e.function == "demstep_n_for_tolerance"
    assert isinstance(e, Exception) and str(e) == e.message


def test_location_fields_come_from_the_struct():
    """where and index are the C struct's (index -1, none, is None); the library
    fills them where its set_status calls give a location."""
    err = _capi.Error()
    err.stat = INVALID
    err.message = b"demstep_scene_set_types: k_n(3): must be positive"
    err.where = b"k_n"
    err.index = 2
    with pytest.raises(demstep.DemstepError) as info:
        check(INVALID, err, "demstep_scene_set_types")
    e = info.value
    assert (e.code, e.where, e.index, e.function) == (INVALID, "k_n", 2, "demstep_scene_set_types")
    assert e.message == "demstep_scene_set_types: k_n(3): must be positive"
    err.where = b""
    err.index = -1
    with pytest.raises(demstep.DemstepError) as info:
        check(INVALID, err, "f")
    assert (info.value.where, info.value.index) == ("", None)
    check(demstep.CONSTANTS["DEMSTEP_OK"], err, "f")  # DEMSTEP_OK raises nothing
    assert ctypes.sizeof(_capi.Error) == 4 + 256 + 64 + 4


def test_free_twice_and_after_free():
    scene = scene3()
    scene.free()
    scene.free()
    e = raised(lambda: scene.compute())
    assert e.message == "demstep_scene_compute: scene is NULL"


def test_snapshot_errors(root, tmp_path):
    e = raised(lambda: demstep.read_snapshot(tmp_path / "no_such.dump"))
    assert e.code == demstep.CONSTANTS["DEMSTEP_IO_ERROR"] and e.code_name == "DEMSTEP_IO_ERROR"
    assert e.message.startswith(f"demstep_snapshot_read: {tmp_path / 'no_such.dump'}")
    e = raised(lambda: demstep.read_snapshot(root / "test/data/liggghts/dump.liggghts", format="xyz"))
    assert e.where == "format" and "'lammps_dump'" in e.message
    e = raised(lambda: demstep.read_snapshot(root / "test/data/liggghts/data.liggghts", type_density=[[1.0]]))
    assert e.where == "type_density"
    bad = tmp_path / "bad.dump"
    bad.write_text((root / "test/data/liggghts/dump.liggghts").read_text().replace("ITEM: ATOMS id", "ITEM: ATOMS idx"))
    e = raised(lambda: demstep.read_snapshot(bad))
    assert e.code == INVALID and str(bad) in e.message and "line" in e.message


def test_pair_errors():
    glass = demstep.Material(6.3e10, 0.22, 2500.0, 1.0e-3)
    e = raised(lambda: demstep.contact_parameters(glass, [6.3e10, 0.22, 2500.0], "liggghts_hertz", 0.9, 1.0))
    assert e.where == "b" and "must have shape (4,)" in e.message
    e = raised(lambda: demstep.contact_parameters(glass, glass, "edem", 0.9, 1.0))
    assert e.where == "convention" and "'mfix_lsd'" in e.message
    e = raised(lambda: demstep.contact_parameters(glass, glass, 42, 0.9, 1.0))
    assert e.code == INVALID and "convention: 42 is not a DEMSTEP_CODE_* value" in e.message
    e = raised(lambda: demstep.peer_time_steps(glass, glass._replace(poisson=np.nan), 0.9, 1.0))
    assert e.code == INVALID and e.function == "demstep_peer_time_steps"
    e = raised(lambda: demstep.peer_time_steps(glass, glass, 1.5, 1.0))
    assert e.code == INVALID and "restitution" in e.message
