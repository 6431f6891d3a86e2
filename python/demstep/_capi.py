"""ctypes declarations of include/demstep.h: the library, its structs, its functions.

The structs are written out field by field as in the header (the test suite
checks names, order and C types against the header's typedefs). The library is
the ``libdemstep.so.0`` the build put beside this file in ``_lib/``, or the one
named by the environment variable ``DEMSTEP_LIBRARY``.
"""
import ctypes as C
import os
from pathlib import Path

from ._header import header_path, read_enum_blocks

_BLOCKS = read_enum_blocks(header_path())
#: Every DEMSTEP_* enum constant of the header.
CONSTANTS = {name: value for block in _BLOCKS for name, value in block.items()}
#: The status codes (the header's enum holding DEMSTEP_OK), by value.
STATUS_NAMES = {value: name for block in _BLOCKS if "DEMSTEP_OK" in block
                for name, value in block.items()}


def library_path():
    """The shared library this package calls."""
    override = os.environ.get("DEMSTEP_LIBRARY")
    if override:
        return Path(override)
    return Path(__file__).resolve().parent / "_lib" / "libdemstep.so.0"


def _load():
    path = library_path()
    if not path.is_file():
        raise ImportError(f"demstep: the shared library {path} is missing: install the package "
                          "with pip (it builds the library) or set DEMSTEP_LIBRARY to a libdemstep.so")
    return C.CDLL(str(path))


LIB = _load()


class Error(C.Structure):
    _fields_ = [("stat", C.c_int), ("message", C.c_char * 256), ("where", C.c_char * 64),
                ("index", C.c_int)]


class Spring(C.Structure):
    _fields_ = [("mass", C.c_double), ("stiffness", C.c_double), ("damping", C.c_double),
                ("compression_only", C.c_int), ("dashpot", C.c_int)]


class SpringState(C.Structure):
    _fields_ = [("x", C.c_double), ("v", C.c_double), ("step", C.c_int64)]


class NRoots(C.Structure):
    _fields_ = [("n_pick", C.c_double), ("n_zero", C.c_double), ("n_lower", C.c_double),
                ("n_upper", C.c_double), ("interval", C.c_int), ("stat", C.c_int),
                ("evaluations", C.c_int)]


class StiffnessResult(C.Structure):
    _fields_ = [("n_star", C.c_double), ("lambda_star", C.c_double), ("period", C.c_double),
                ("dt", C.c_double), ("stiffness_actual", C.c_double),
                ("lambda_star_stat", C.c_int), ("excluded", C.c_int)]


class Contact(C.Structure):
    _fields_ = [("onset", C.c_double), ("contact_time", C.c_double), ("restitution", C.c_double),
                ("max_overlap", C.c_double), ("steps", C.c_int64), ("stable", C.c_int)]


class SceneResult(C.Structure):
    _fields_ = [
        ("omega_max", C.c_double), ("dt_critical_eigen", C.c_double),
        ("omega_bound", C.c_double), ("dt_critical_bound", C.c_double),
        ("dt_contact_rule", C.c_double), ("damping_ratio_top", C.c_double),
        ("dt_critical_damped", C.c_double),
        ("n_dof", C.c_int), ("n_springs", C.c_int), ("dof_per_particle", C.c_int),
        ("eigen_computed", C.c_int), ("rotation", C.c_int), ("tangential", C.c_int),
        ("periodic", C.c_int), ("prestress", C.c_int),
        ("eigen_tolerance", C.c_double), ("eigen_residual", C.c_double),
        ("omega_upper", C.c_double), ("dt_critical_safe", C.c_double),
        ("eigen_products", C.c_int64), ("eigen_solver", C.c_int), ("eigen_converged", C.c_int),
        ("dt_critical_damped_bound", C.c_double), ("damped_exact", C.c_int),
        ("damped_solves", C.c_int)]


class SnapshotInfo(C.Structure):
    _fields_ = [("n", C.c_int), ("format", C.c_int), ("frame", C.c_int), ("n_frames", C.c_int),
                ("timestep", C.c_int64), ("has_velocity", C.c_int), ("has_omega", C.c_int),
                ("has_mass", C.c_int), ("has_density", C.c_int), ("has_box", C.c_int),
                ("periodic", C.c_int * 3), ("lo", C.c_double * 3), ("hi", C.c_double * 3)]


class Material(C.Structure):
    _fields_ = [("young", C.c_double), ("poisson", C.c_double), ("density", C.c_double),
                ("radius", C.c_double)]


class MaterialPair(C.Structure):
    _fields_ = [("a", Material), ("b", Material), ("restitution", C.c_double),
                ("restitution_t", C.c_double), ("impact_velocity", C.c_double),
                ("contact_time", C.c_double), ("stiffness", C.c_double)]


class ContactParameters(C.Structure):
    _fields_ = [("k_n", C.c_double), ("k_t", C.c_double), ("gamma_n", C.c_double),
                ("gamma_t", C.c_double), ("overlap", C.c_double), ("t_contact", C.c_double),
                ("code_collision_time", C.c_double), ("m_star", C.c_double), ("dt_code", C.c_double)]


class PeerSteps(C.Structure):
    _fields_ = [("rayleigh", C.c_double), ("rayleigh_yade", C.c_double), ("hertz_duration", C.c_double),
                ("hertz_liggghts", C.c_double), ("dt", C.c_double * 9)]


_p = C.c_void_p
_i = C.c_int
_d = C.c_double

#: name: argument types (every function returns int, its status)
PROTOTYPES = {
    "demstep_spring_new": [_d, _d, _d, _i, _i, _p, _p],
    "demstep_spring_step": [_p, _d, _p, _p],
    "demstep_critical_time_step": [_p, _p, _p],
    "demstep_harmonic_error": [_d, _d, _d, _p, _p],
    "demstep_n_roots": [_d, _d, _i, _d, _i, _d, _d, _p, _p],
    "demstep_simulated_stiffness": [_d, _d, _d, _p, _i, _i, _d, _i, _i, _p, _p, _p, _p, _p],
    "demstep_scene_create": [_i, _p, _p],
    "demstep_scene_free": [_p, _p],
    "demstep_scene_set_particles": [_p, _i, _p, _p, _p, _p, _p, _p, _p],
    "demstep_scene_add_bonds": [_p, _i, _p, _p],
    "demstep_scene_set_bond_stiffness": [_p, _d, _d, _p],
    "demstep_scene_set_bond_model": [_p, _i, _i, _p, _p],
    "demstep_scene_set_bodies": [_p, _p, _d, _i, _p, _p, _p, _p],
    "demstep_scene_body_peer_steps": [_p, _p, _p, _p],
    "demstep_scene_set_contact_law": [_p, _i, _d, _d, _p],
    "demstep_scene_set_types": [_p, _i, _p, _p, _p, _p],
    "demstep_scene_set_hertz_types": [_p, _i, _p, _p, _p, _p],
    "demstep_scene_set_materials": [_p, _i, _p, _p, _p, _p, _p, _i, _d, _d, _i, _i, _p],
    "demstep_scene_add_walls": [_p, _i, _p, _p, _p],
    "demstep_scene_set_contacts": [_p, _i, _p, _p, _p],
    "demstep_scene_set_effects": [_p, _i, _p],
    "demstep_scene_set_cell": [_p, _p, _p, _p, _p],
    "demstep_scene_set_damping": [_p, _d, _p],
    "demstep_scene_set_dashpots": [_p, _d, _d, _d, _p],
    "demstep_scene_set_rolling": [_p, _d, _d, _p],
    "demstep_scene_set_gravity": [_p, _p, _p],
    "demstep_scene_set_eigen_solver": [_p, _i, _d, _p],
    "demstep_scene_compute": [_p, _i, _d, _i, _i, _p, C.c_size_t, _p],
    "demstep_contact_with_onset": [_d, _d, _d, _p, _p],
    "demstep_n_for_tolerance": [_i, _d, _d, _d, _p, _p],
    "demstep_snapshot_read": [C.c_char_p, _i, _i, _i, _p, _p, _p, _p],
    "demstep_snapshot_get": [_p, _p, _p, _p, _p, _p, _p, _p, _p, _p],
    "demstep_snapshot_free": [_p, _p],
    "demstep_contact_parameters": [_p, _i, _p, _p],
    "demstep_peer_time_steps": [_p, _p, _p],
    "demstep_solver_compute": [_i, _i, _p, _p, _p, _p, _i, _p, _i, _p, _p, _p, _p, _i, _p, _p, _p, _p, _p,
                               _p, _p, _i, _d, _p, C.c_size_t, _p],
    "demstep_solver_participation": [_i, _i, _p, _p, _p, _p, _i, _p, _i, _p, _p, _p, _p, _i, _p, _p, _p, _p,
                                     _p, _p, _p, _i, _d, _p, C.c_size_t, _p, _p, _p, _p],
}

for _name, _args in PROTOTYPES.items():
    _f = getattr(LIB, _name)
    _f.argtypes = _args
    _f.restype = C.c_int
