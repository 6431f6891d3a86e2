"""demstep from Python: exact DEM time-step limits through the library's C API.

numpy arrays go in, results come out as records with the fields of the C API's
result structs (``include/demstep.h``), and every status other than DEMSTEP_OK
is raised as :class:`DemstepError` (code, message, where, index).

    with demstep.Scene(3) as scene:          # 3 dimensions
        scene.set_particles(x, mass, radius)  # x: (n, 3), mass and radius: (n,)
        scene.set_contact_law("linear", 1.0e5, 0.0)
        print(scene.compute().dt_critical_eigen)
"""
import ctypes as C

import numpy as np

from . import _capi
from ._arrays import as_array, count, pointer
from ._common import CONSTANTS, call as _call, enum as _enum, fill as _fill, record as _record
from ._errors import DemstepError
from ._scene import Scene, SceneResult, solver_critical_steps, solver_participation
from ._snapshot import Snapshot, read_snapshot
from ._material import PEER_RULES, ContactParameters, Material, PeerSteps, contact_parameters, peer_time_steps

__all__ = ["DemstepError", "CONSTANTS", "Spring", "SpringState", "NRoots", "StiffnessResult",
           "Contact", "SceneResult", "Scene", "harmonic_error", "n_roots", "simulated_stiffness",
           "contact_with_onset", "n_for_tolerance", "library_path", "Snapshot", "read_snapshot",
           "Material", "ContactParameters", "PeerSteps", "PEER_RULES", "contact_parameters", "peer_time_steps",
           "solver_critical_steps", "solver_participation"]

library_path = _capi.library_path


SpringState = _record(_capi.SpringState, "SpringState",
                      "Overlap x (positive in compression), half-step velocity v, steps taken.")
NRoots = _record(_capi.NRoots, "NRoots", "One lambda's scan (struct demstep_nroots).")
StiffnessResult = _record(_capi.StiffnessResult, "StiffnessResult",
                          "The simulated-stiffness procedure's answer (struct demstep_stiffness_result) "
                          "with each lambda's pick n_pick and row_status.",
                          extra=[("n_pick", np.ndarray), ("row_status", np.ndarray)])
Contact = _record(_capi.Contact, "Contact", "The exact discrete contact (struct demstep_contact).")


class Spring:
    """A mass on a linear spring with a viscous dashpot c = 2 zeta sqrt(K M) (demstep_spring_new).

    ``dashpot``: "lagged" or "centred"; ``compression_only``: a contact (True) or a bond.
    The fields of struct demstep_spring are attributes (``spring.damping`` is c).
    """

    def __init__(self, mass, stiffness, damping_ratio=0.0, compression_only=True, dashpot="lagged"):
        self._struct = _capi.Spring()
        kind = _enum("DEMSTEP_DASHPOT_", dashpot, "demstep_spring_new", "dashpot")
        _call("demstep_spring_new", mass, stiffness, damping_ratio, int(bool(compression_only)), kind,
              C.byref(self._struct))

    def __getattr__(self, name):
        if name in {field for field, _ in _capi.Spring._fields_}:
            return getattr(self._struct, name)
        raise AttributeError(name)

    def __repr__(self):
        return "Spring(" + ", ".join(f"{f}={getattr(self._struct, f)!r}" for f, _ in _capi.Spring._fields_) + ")"

    def critical_time_step(self):
        """The largest stable step (demstep_critical_time_step)."""
        dt = C.c_double()
        _call("demstep_critical_time_step", C.byref(self._struct), C.byref(dt))
        return dt.value

    def step(self, dt, state):
        """One central-difference step from ``state`` (a SpringState); the new SpringState."""
        s = _capi.SpringState(state.x, state.v, state.step)
        _call("demstep_spring_step", C.byref(self._struct), dt, C.byref(s))
        return _fill(SpringState, s)


def harmonic_error(n_per_period, lambda_, n_steps):
    """The paper's error E(N, lambda, n) (demstep_harmonic_error)."""
    e = C.c_double()
    _call("demstep_harmonic_error", n_per_period, lambda_, n_steps, C.byref(e))
    return e.value


def n_roots(lambda_, tolerance, steps_kind="fraction", steps_value=0.5, pick="largest_step",
            n_max=0.0, resolution=0.0):
    """Roots and admissible N of E for one lambda (demstep_n_roots): an NRoots."""
    function = "demstep_n_roots"
    result = _capi.NRoots()
    _call(function, lambda_, tolerance, _enum("DEMSTEP_STEPS_", steps_kind, function, "steps_kind"),
          steps_value, _enum("DEMSTEP_PICK_", pick, function, "pick"), n_max, resolution,
          C.byref(result))
    return _fill(NRoots, result)


def simulated_stiffness(mass, stiffness, tolerance, lambdas, steps_kind="fraction", steps_value=0.5,
                        pick="largest_step", aggregate="mean", weights=None):
    """The whole procedure over increasing lambdas in (0, 1) (demstep_simulated_stiffness)."""
    function = "demstep_simulated_stiffness"
    lam = as_array(lambdas, function, "lambdas", (None,), "float")
    n = count(lam, function, "lambdas")
    w = None if weights is None else as_array(weights, function, "weights", (n,), "float",
                                              "one per lambda")
    picks = np.zeros(n)
    rows = np.zeros(n, dtype=np.int32)
    result = _capi.StiffnessResult()
    _call(function, mass, stiffness, tolerance, pointer(lam), n,
          _enum("DEMSTEP_STEPS_", steps_kind, function, "steps_kind"), steps_value,
          _enum("DEMSTEP_PICK_", pick, function, "pick"),
          _enum("DEMSTEP_AGGREGATE_", aggregate, function, "aggregate"), pointer(w),
          pointer(picks), pointer(rows), C.byref(result))
    return _fill(StiffnessResult, result, n_pick=picks, row_status=rows)


def contact_with_onset(n_per_period, onset, damping_ratio=0.0):
    """The discrete contact at N = T/dt and onset s in (0, 1] (demstep_contact_with_onset)."""
    contact = _capi.Contact()
    _call("demstep_contact_with_onset", n_per_period, onset, damping_ratio, C.byref(contact))
    return _fill(Contact, contact)


def n_for_tolerance(quantity, tolerance, damping_ratio=0.0, n_max=0.0):
    """The smallest N = T/dt within tolerance at N and above (demstep_n_for_tolerance).

    ``quantity``: "restitution", "contact_time", "overlap" or "period".
    """
    function = "demstep_n_for_tolerance"
    n = C.c_double()
    _call(function, _enum("DEMSTEP_QUANTITY_", quantity, function, "quantity"), tolerance,
          damping_ratio, n_max, C.byref(n))
    return n.value


