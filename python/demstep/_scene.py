"""Scene: the C API's scene handle, built call by call from numpy arrays."""
import ctypes as C
import numbers

import numpy as np

from . import _capi
from ._arrays import as_array, count, pointer
from ._common import call, enum, fill, record

SceneResult = record(_capi.SceneResult, "SceneResult",
                     "The critical steps of a scene (struct demstep_scene_result).")

_EFFECT = "DEMSTEP_EFFECT_"


class Scene:
    """A scene of ``dim`` (1 to 3) dimensions (demstep_scene_create).

    Each method is one C call of the same name (``set_particles`` is
    demstep_scene_set_particles) with the library's checks; arrays are numpy
    arrays with one row per particle, bond, contact, wall or type, and particle,
    bond, type and contact numbers are 0-based. A call the library refuses leaves
    the scene unusable (the C API's rule): build a new one. A shape or dtype the
    package refuses before the call leaves it as it was. Use it in a ``with``
    block, or call ``free()``.
    """

    def __init__(self, dim):
        self.dim = dim
        self._handle = C.c_void_p()
        self.n = 0
        call("demstep_scene_create", dim, C.byref(self._handle))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.free()

    def __del__(self):
        if getattr(self, "_handle", None) is not None and self._handle.value:
            try:
                self.free()
            except Exception:  # at interpreter exit the module may be gone: the OS frees it
                pass

    def free(self):
        """Free the scene (demstep_scene_free); a second free does nothing."""
        call("demstep_scene_free", C.byref(self._handle))

    def _points(self, value, function, where, rows, meaning):
        """(rows, dim) coordinates; in 1D a flat array of rows values is accepted too."""
        array = np.asarray(value) if self.dim == 1 else value
        if self.dim == 1 and getattr(array, "ndim", 0) == 1:
            array = array.reshape(-1, 1)
        return as_array(array, function, where, (rows, self.dim), "float", meaning)

    def set_particles(self, x, mass, radius, fixed=None, inertia=None, velocity=None):
        """The particles, once: x (n, dim); mass, radius, fixed, inertia (n,); velocity (n, dim)."""
        f = "demstep_scene_set_particles"
        x = self._points(x, f, "x", None, "dim coordinates per particle")
        n = count(x, f, "x")
        per = "one per particle"
        m = as_array(mass, f, "mass", (n,), "float", per)
        r = as_array(radius, f, "radius", (n,), "float", per)
        fx = None if fixed is None else as_array(fixed, f, "fixed", (n,), "flag", per)
        inert = None if inertia is None else as_array(inertia, f, "inertia", (n,), "float", per)
        v = None if velocity is None else self._points(velocity, f, "velocity", n, "dim components per particle")
        call(f, self._handle, n, pointer(x), pointer(m), pointer(r), pointer(fx), pointer(inert), pointer(v))
        self.n = n

    def add_bonds(self, bonds):
        """Bonds: (n_bonds, 2) particle numbers."""
        f = "demstep_scene_add_bonds"
        b = as_array(bonds, f, "bonds", (None, 2), "int", "2 particle numbers per bond")
        call(f, self._handle, count(b, f, "bonds"), pointer(b))

    def set_bond_stiffness(self, k_bond, k_bond_tangential=0.0):
        """Every bond's normal (> 0) and tangential (>= 0) stiffness."""
        call("demstep_scene_set_bond_stiffness", self._handle, k_bond, k_bond_tangential)

    def set_bond_model(self, model, parameters):
        """Every bond's law as a DEM code makes it: model "pfc" (kbar_n, kbar_s, lambda),
        "musen" (E, G, diameter), "yade" (young, poisson, alpha_kr, alpha_ktw) or "lammps"
        (K_r, K_s, K_t, K_b, gamma_n, gamma_s, gamma_r, gamma_t), or a DEMSTEP_BOND_* value."""
        f = "demstep_scene_set_bond_model"
        p = as_array(parameters, f, "parameters", (None,), "float", "the model's inputs in its order")
        call(f, self._handle, enum("DEMSTEP_BOND_", model, f, "model"), len(p), pointer(p))

    def set_bodies(self, body_of, density=0.0, mass=None, com=None, inertia=None):
        """Rigid bodies, once: body_of (n,) ids (0: a particle on its own). Without mass:
        each body's mass and tensor from its members (density > 0: their masses from it);
        with mass (n_bodies,), com (n_bodies, 3) and inertia (n_bodies, 3, 3): as given."""
        f = "demstep_scene_set_bodies"
        b = as_array(body_of, f, "body_of", (self.n,), "int", "one per particle")
        if mass is None:
            call(f, self._handle, pointer(b), density, 0, None, None, None)
            return
        m = as_array(mass, f, "mass", (None,), "float", "one per body")
        n_bodies = count(m, f, "mass")
        c = as_array(com, f, "com", (n_bodies, 3), "float", "3 per body")
        j = as_array(inertia, f, "inertia", (n_bodies, 3, 3), "float", "3 x 3 per body")
        call(f, self._handle, pointer(b), density, n_bodies, pointer(m), pointer(c), pointer(j))

    def body_peer_steps(self):
        """The peers' rules on the bodies, raw: (Yade's GlobalStiffnessTimeStepper, exaDEM's)."""
        gst, exadem = C.c_double(), C.c_double()
        call("demstep_scene_body_peer_steps", self._handle, C.byref(gst), C.byref(exadem))
        return gst.value, exadem.value

    def set_contact_law(self, law, normal, tangential=0.0):
        """"linear" with k_n, k_t or "hertz" with E*, G*."""
        f = "demstep_scene_set_contact_law"
        call(f, self._handle, enum("DEMSTEP_LAW_", law, f, "law"), normal, tangential)

    def set_types(self, types, k_normal, k_tangential=None):
        """Linear materials per type: types (n,); k_normal, k_tangential (n_types, n_types)."""
        f = "demstep_scene_set_types"
        kn = as_array(k_normal, f, "k_normal", (None, None), "float")
        n_types = count(kn, f, "k_normal")
        kn = as_array(kn, f, "k_normal", (n_types, n_types), "float", "n_types x n_types")
        kt = None if k_tangential is None else as_array(k_tangential, f, "k_tangential",
                                                        (n_types, n_types), "float", "n_types x n_types")
        t = as_array(types, f, "types", (self.n,), "int", "one per particle")
        call(f, self._handle, n_types, pointer(t), pointer(kn), pointer(kt))

    def set_hertz_types(self, types, young, poisson):
        """Hertz materials per type: types (n,); young, poisson (n_types,)."""
        f = "demstep_scene_set_hertz_types"
        e = as_array(young, f, "young", (None,), "float", "one per type")
        n_types = count(e, f, "young")
        nu = as_array(poisson, f, "poisson", (n_types,), "float", "one per type")
        t = as_array(types, f, "types", (self.n,), "int", "one per particle")
        call(f, self._handle, n_types, pointer(t), pointer(e), pointer(nu))

    def set_materials(self, types, young, poisson, density, radius, code, restitution,
                      impact_velocity, wall_type=-1, tangential_damping=True):
        """Materials per type in one code's convention (demstep_scene_set_materials).

        types (n,); young, poisson, density, radius (n_types,); code: "liggghts_hooke",
        "liggghts_hertz", "yade_frictphys", "yade_viscelphys", "mfix_lsd",
        "mfix_hertzian", "mercurydpm_linear", "lammps_hooke", "lammps_hertz_material"
        (or a DEMSTEP_CODE_* value); wall_type -1: each particle's own type.
        """
        f = "demstep_scene_set_materials"
        e = as_array(young, f, "young", (None,), "float", "one per type")
        n_types = count(e, f, "young")
        per_type = {name: as_array(value, f, name, (n_types,), "float", "one per type")
                    for name, value in (("poisson", poisson), ("density", density), ("radius", radius))}
        t = as_array(types, f, "types", (self.n,), "int", "one per particle")
        call(f, self._handle, n_types, pointer(t), pointer(e), pointer(per_type["poisson"]),
             pointer(per_type["density"]), pointer(per_type["radius"]),
             enum("DEMSTEP_CODE_", code, f, "convention"), restitution, impact_velocity, wall_type,
             int(bool(tangential_damping)))

    def add_walls(self, points, normals):
        """Walls: a point and a normal into the domain per wall, (n_walls, dim) each."""
        f = "demstep_scene_add_walls"
        p = self._points(points, f, "points", None, "dim coordinates per wall")
        n_walls = count(p, f, "points")
        q = self._points(normals, f, "normals", n_walls, "dim components per wall")
        call(f, self._handle, n_walls, pointer(p), pointer(q))

    def set_contacts(self, pairs, k):
        """An explicit contact list: pairs (n_contacts, 2) particle numbers, k (n_contacts, 2) k_n, k_t."""
        f = "demstep_scene_set_contacts"
        p = as_array(pairs, f, "pairs", (None, 2), "int", "2 particle numbers per contact")
        n_contacts = count(p, f, "pairs")
        kk = as_array(k, f, "k", (n_contacts, 2), "float", "k_n, k_t per contact")
        call(f, self._handle, n_contacts, pointer(p), pointer(kk))

    def set_effects(self, effects):
        """The effects: an int (a sum of DEMSTEP_EFFECT_* flags) or names ("contacts", "gravity",
        "damping", "local_damping", "walls", "rotation")."""
        f = "demstep_scene_set_effects"
        if isinstance(effects, str):
            effects = [effects]
        if isinstance(effects, numbers.Integral) and not isinstance(effects, bool):
            effects = int(effects)
        else:
            effects = sum({enum(_EFFECT, name, f, "effects") for name in effects})
        call(f, self._handle, effects)

    def set_cell(self, periodic, lo, hi):
        """A periodic orthorhombic cell [lo, hi): periodic (dim,) flags, lo and hi (dim,)."""
        f = "demstep_scene_set_cell"
        per = as_array(periodic, f, "periodic", (self.dim,), "flag", "one per axis")
        low = as_array(lo, f, "lo", (self.dim,), "float", "one per axis")
        high = as_array(hi, f, "hi", (self.dim,), "float", "one per axis")
        call(f, self._handle, pointer(per), pointer(low), pointer(high))

    def set_damping(self, damping_ratio):
        """The viscous damping ratio of the "damping" effect."""
        call("demstep_scene_set_damping", self._handle, damping_ratio)

    def set_dashpots(self, tangential, rolling=0.0, drag=0.0):
        """The tangential and rolling damping ratios and a drag to the ground."""
        call("demstep_scene_set_dashpots", self._handle, tangential, rolling, drag)

    def set_rolling(self, rolling_ratio, twisting_ratio=0.0):
        """Rolling and twisting springs k_r = rolling_ratio k_t R*^2, k_w = twisting_ratio k_t R*^2."""
        call("demstep_scene_set_rolling", self._handle, rolling_ratio, twisting_ratio)

    def set_gravity(self, gravity):
        """The gravity vector (dim,) of the "gravity" effect."""
        f = "demstep_scene_set_gravity"
        g = as_array(gravity, f, "gravity", (self.dim,), "float", "one per axis")
        call(f, self._handle, pointer(g))

    def set_eigen_solver(self, solver="auto", tolerance=0.0):
        """"auto", "dense", "lanczos" or "none", and the Lanczos tolerance (<= 0: the default 1e-6)."""
        f = "demstep_scene_set_eigen_solver"
        call(f, self._handle, enum("DEMSTEP_EIGEN_", solver, f, "solver"), tolerance)

    def compute(self, hertz_linearization="current", impact_velocity=0.0, prestress=False,
                max_eigen_dof=0):
        """The critical steps at the current configuration: a SceneResult."""
        f = "demstep_scene_compute"
        result = _capi.SceneResult()
        call(f, self._handle, enum("DEMSTEP_HERTZ_", hertz_linearization, f, "hertz_linearization"),
             impact_velocity, int(bool(prestress)), max_eigen_dof, C.byref(result),
             C.sizeof(result))
        return fill(SceneResult, result)


def _solver_arguments(f, x, mass, radius, pairs, k_n, k_t, c_n, c_t, inertia, wall_point, wall_normal,
                      wall_k, wall_damping, periodic, cell_lo, cell_hi, solver, tolerance):
    """The C arguments of the solver-facing calls (demstep_solver_compute and
    demstep_solver_participation) before the result, and (n, n_contacts)."""
    x = as_array(x, f, "x", (None, None), "float", "dim coordinates per particle")
    n = count(x, f, "x")
    dim = x.shape[1]
    per = "one per particle"
    m = as_array(mass, f, "mass", (n,), "float", per)
    r = as_array(radius, f, "radius", (n,), "float", per)
    inert = None if inertia is None else as_array(inertia, f, "inertia", (n,), "float", per)
    p = as_array(pairs, f, "pairs", (None, 2), "int", "2 particle numbers per contact")
    nc = count(p, f, "pairs")
    kn = np.atleast_1d(k_n)
    nv = kn.size
    per_contact = "1 value or one per contact"
    kn = as_array(kn, f, "k_n", (nv,), "float", per_contact)
    opt = [None if v is None else as_array(np.atleast_1d(v), f, name, (nv,), "float", per_contact)
           for v, name in ((k_t, "k_t"), (c_n, "c_n"), (c_t, "c_t"))]
    nw = 0
    wp = wn = wk = wd = None
    if wall_point is not None:
        wp = as_array(wall_point, f, "wall_point", (None, dim), "float", "dim values per wall")
        nw = count(wp, f, "wall_point")
        wn = as_array(wall_normal, f, "wall_normal", (nw, dim), "float", "dim values per wall")
        wk = as_array(wall_k, f, "wall_k", (2,), "float", "k_n and k_t")
        wd = None if wall_damping is None else as_array(wall_damping, f, "wall_damping", (2,), "float",
                                                        "zeta_n and zeta_t")
    per_axis = "dim values"
    per_flag = None if periodic is None else as_array(periodic, f, "periodic", (dim,), "flag", per_axis)
    lo = None if cell_lo is None else as_array(cell_lo, f, "cell_lo", (dim,), "float", per_axis)
    hi = None if cell_hi is None else as_array(cell_hi, f, "cell_hi", (dim,), "float", per_axis)
    # (the arrays are returned with the pointers so that they outlive the call)
    args = [dim, n, pointer(x), pointer(m), pointer(r), pointer(inert), nc, pointer(p), nv, pointer(kn),
            pointer(opt[0]), pointer(opt[1]), pointer(opt[2]), nw, pointer(wp), pointer(wn), pointer(wk),
            pointer(wd), pointer(per_flag), pointer(lo), pointer(hi), enum("DEMSTEP_EIGEN_", solver, f, "solver"),
            tolerance]
    return args, (x, m, r, inert, p, kn, opt, wp, wn, wk, wd, per_flag, lo, hi), n, nc


def solver_critical_steps(x, mass, radius, pairs, k_n, k_t=None, c_n=None, c_t=None, inertia=None,
                          wall_point=None, wall_normal=None, wall_k=None, wall_damping=None,
                          periodic=None, cell_lo=None, cell_hi=None, solver="auto", tolerance=0.0):
    """The critical steps from a solver's own arrays (demstep_solver_compute): no
    scene and no contact search. x (n, dim); mass, radius, inertia (n,); pairs
    (n_contacts, 2), 0-based; k_n, k_t, c_n, c_t one value or one per contact;
    walls: points and normals (n_walls, dim), wall_k = (k_n, k_t), wall_damping
    = (zeta_n, zeta_t); periodic (dim flags) with cell_lo, cell_hi (dim). A
    SceneResult."""
    f = "demstep_solver_compute"
    args, _keep, _, _ = _solver_arguments(f, x, mass, radius, pairs, k_n, k_t, c_n, c_t, inertia, wall_point,
                                          wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi,
                                          solver, tolerance)
    result = _capi.SceneResult()
    call(f, *args, C.byref(result), C.sizeof(result))
    return fill(SceneResult, result)


def solver_participation(x, mass, radius, pairs, k_n, k_t=None, c_n=None, c_t=None, inertia=None,
                         wall_point=None, wall_normal=None, wall_k=None, wall_damping=None,
                         periodic=None, cell_lo=None, cell_hi=None, solver="auto", tolerance=0.0):
    """The solve of `solver_critical_steps` (same arguments) and which particles
    and contacts carry its top undamped mode (demstep_solver_participation): a
    SceneResult, the particles' shares (n,), the listed contacts' (n_contacts,)
    and each particle's wall contacts' (n,)."""
    f = "demstep_solver_participation"
    args, _keep, n, nc = _solver_arguments(f, x, mass, radius, pairs, k_n, k_t, c_n, c_t, inertia, wall_point,
                                           wall_normal, wall_k, wall_damping, periodic, cell_lo, cell_hi,
                                           solver, tolerance)
    result = _capi.SceneResult()
    shares = np.zeros(n)
    contact_shares = np.zeros(max(nc, 1))
    wall_shares = np.zeros(n)
    call(f, *args, C.byref(result), C.sizeof(result), pointer(shares), pointer(contact_shares),
         pointer(wall_shares))
    return fill(SceneResult, result), shares, contact_shares[:nc], wall_shares
