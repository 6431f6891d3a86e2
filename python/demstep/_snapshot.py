"""read_snapshot: the particles of a LAMMPS/LIGGGHTS dump or data file or a Yade text export."""
import ctypes as C
import dataclasses
import os

import numpy as np

from . import _capi
from ._arrays import as_array, pointer
from ._common import call, enum


@dataclasses.dataclass(frozen=True)
class Snapshot:
    """A snapshot (demstep_snapshot_info's fields, then the arrays of demstep_snapshot_get).

    ``type`` is 0-based (the file's type minus 1, Yade's matId); x, v, omega are
    (n, 3); velocities, angular velocities, masses and densities are 0 where the
    file had none (see the has_* flags); periodic, lo, hi are per axis.
    """
    n: int
    format: int
    frame: int
    n_frames: int
    timestep: int
    has_velocity: bool
    has_omega: bool
    has_mass: bool
    has_density: bool
    has_box: bool
    periodic: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    id: np.ndarray
    type: np.ndarray
    x: np.ndarray
    v: np.ndarray
    omega: np.ndarray
    radius: np.ndarray
    mass: np.ndarray
    density: np.ndarray


def read_snapshot(path, format="auto", frame=0, type_density=None):
    """Read a snapshot (demstep_snapshot_read): ``format`` "auto", "lammps_dump",
    "lammps_data" or "yade_text"; ``frame`` a dump's frame (1-based, 0 the last,
    negative from the end); ``type_density`` a density per type for the masses
    when the file has none."""
    f = "demstep_snapshot_read"
    kind = enum("DEMSTEP_SNAPSHOT_", format, f, "format")
    rho = None if type_density is None else as_array(type_density, f, "type_density", (None,), "float",
                                                     "one per type")
    handle = C.c_void_p()
    info = _capi.SnapshotInfo()
    call(f, os.fsencode(path), kind, frame, 0 if rho is None else len(rho), pointer(rho), C.byref(handle),
         C.byref(info))
    try:
        n = info.n
        arrays = {"id": np.zeros(n, np.int64), "type": np.zeros(n, np.int32), "x": np.zeros((n, 3)),
                  "v": np.zeros((n, 3)), "omega": np.zeros((n, 3)), "radius": np.zeros(n),
                  "mass": np.zeros(n), "density": np.zeros(n)}
        call("demstep_snapshot_get", handle, *(pointer(a) for a in arrays.values()))
    finally:
        call("demstep_snapshot_free", C.byref(handle))
    return Snapshot(n=n, format=info.format, frame=info.frame, n_frames=info.n_frames, timestep=info.timestep,
                    has_velocity=bool(info.has_velocity), has_omega=bool(info.has_omega),
                    has_mass=bool(info.has_mass), has_density=bool(info.has_density),
                    has_box=bool(info.has_box), periodic=np.array(info.periodic[:], dtype=bool),
                    lo=np.array(info.lo[:]), hi=np.array(info.hi[:]), **arrays)
