"""A pair of particle types: its contact in each code's convention and the peers' rules."""
import collections
import ctypes as C
import dataclasses

from . import _capi
from ._arrays import as_array
from ._common import CONSTANTS, call, enum, fill, record

#: One particle type (struct demstep_material).
Material = collections.namedtuple("Material", "young poisson density radius")

ContactParameters = record(_capi.ContactParameters, "ContactParameters",
                           "A pair's contact in one code's convention (struct demstep_contact_parameters).")

_PEER = "DEMSTEP_PEER_"
#: The peers' rules by name, in the order of demstep_peer_steps.dt.
PEER_RULES = tuple(name[len(_PEER):].lower() for name, _ in
                   sorted(((n, v) for n, v in CONSTANTS.items() if n.startswith(_PEER)), key=lambda nv: nv[1]))


@dataclasses.dataclass(frozen=True)
class PeerSteps:
    """A pair's time scales and the step each peer's rule picks (struct demstep_peer_steps);
    ``dt`` maps each rule's name ("edem_rayleigh_20", ...) to its step."""
    rayleigh: float
    rayleigh_yade: float
    hertz_duration: float
    hertz_liggghts: float
    dt: dict


def _pair(function, a, b, restitution, impact_velocity, restitution_t, contact_time, stiffness):
    pair = _capi.MaterialPair()
    for where, value, target in (("a", a, pair.a), ("b", b, pair.b)):
        values = as_array(value, function, where, (4,), "float", "young, poisson, density, radius")
        target.young, target.poisson, target.density, target.radius = (float(v) for v in values)
    pair.restitution, pair.restitution_t = restitution, restitution_t
    pair.impact_velocity, pair.contact_time, pair.stiffness = impact_velocity, contact_time, stiffness
    return pair


def contact_parameters(a, b, code, restitution, impact_velocity, restitution_t=0.0, contact_time=0.0,
                       stiffness=0.0):
    """The contact of types a and b (each a Material or young, poisson, density, radius) in one
    code's convention (demstep_contact_parameters): k_n, k_t, gamma_n, gamma_t, overlap,
    t_contact, code_collision_time, m_star and dt_code, the exact limit as that code steps it."""
    f = "demstep_contact_parameters"
    pair = _pair(f, a, b, restitution, impact_velocity, restitution_t, contact_time, stiffness)
    out = _capi.ContactParameters()
    call(f, C.byref(pair), enum("DEMSTEP_CODE_", code, f, "convention"), C.byref(out))
    return fill(ContactParameters, out)


def peer_time_steps(a, b, restitution, impact_velocity, restitution_t=0.0, contact_time=0.0, stiffness=0.0):
    """The time scales of types a and b and each peer's rule (demstep_peer_time_steps)."""
    f = "demstep_peer_time_steps"
    pair = _pair(f, a, b, restitution, impact_velocity, restitution_t, contact_time, stiffness)
    out = _capi.PeerSteps()
    call(f, C.byref(pair), C.byref(out))
    return PeerSteps(out.rayleigh, out.rayleigh_yade, out.hertz_duration, out.hertz_liggghts,
                     dict(zip(PEER_RULES, out.dt[:])))
