"""The exact limit of a running Yade simulation: ``demstep.yade.critical_steps(O)``.

Inside a Yade script (Yade's Python 3; the package and numpy on its path)::

    import demstep.yade
    result = demstep.yade.critical_steps(O)        # a demstep.SceneResult
    print(result.dt_critical_eigen, O.dt)

What is read from ``O`` (Yade's Python API: ``O.bodies``, ``O.interactions``,
``O.periodic``, ``O.cell``):

- every sphere (``b.shape.radius``, ``b.state.pos``, ``b.state.mass``,
  ``b.state.inertia[0]``, ``b.state.vel``); a body with ``b.dynamic`` false, or
  with all six ``blockedDOFs``, is fixed; partly blocked DOFs and clumps are
  refused (DemstepError naming the body);
- every real interaction (``i.isReal``) as an explicit linear contact with
  Yade's own ``i.phys.kn`` and ``i.phys.ks``: between two spheres as a particle
  pair, whose direction demstep takes from the positions (nearest periodic
  image); Yade's ``i.geom.normal`` is checked against it (a contact through
  another image is refused); between a sphere and a facet, wall or box, as a
  contact with a fixed twin of the sphere placed along Yade's normal at Yade's
  ``i.geom.penetrationDepth`` (so the spring acts at the contact point with the
  sphere's radius as its lever arm, as a wall contact);
- the periodic cell: ``O.cell.hSize`` must be diagonal (orthorhombic);
  ``[0, size)`` on every axis.

Rotations are counted (Yade's spheres rotate). Per-contact dashpots
(``ViscElPhys`` ``cn``, ``cs``) and rolling or twisting springs (``CohFrictPhys``
``kr``, ``ktw``) cannot be given per contact through the C API: when a contact
has them the result is the undamped limit of the springs ``kn``, ``ks`` and a
``UserWarning`` says so (validation/yade/reference_damped.py has the damped one).
"""
import warnings

import numpy as np

from ._errors import invalid
from ._scene import Scene

FUNCTION = "demstep.yade"


def _vector(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def _is_sphere(body):
    return type(body.shape).__name__ == "Sphere"


def _read_bodies(O):
    """Rows of the spheres: body ids, positions, masses, radii, fixed flags, inertias, velocities."""
    rows, ids, x, m, r, fixed, inertia, v = {}, [], [], [], [], [], [], []
    for body in O.bodies:
        if body is None:
            continue  # an erased body
        if getattr(body, "isClump", False) or getattr(body, "isClumpMember", False):
            raise invalid(FUNCTION, "O.bodies", "clumps are not supported yet (rigid bodies)", index=body.id)
        if not _is_sphere(body):
            continue  # facets, walls, boxes: taken from their interactions
        blocked = getattr(body.state, "blockedDOFs", "")
        all_blocked = sorted(blocked) == sorted("xyzXYZ")
        if blocked and not all_blocked:
            raise invalid(FUNCTION, "O.bodies", f"blockedDOFs '{blocked}': only none or all six are "
                          "supported", index=body.id)
        rows[body.id] = len(ids)
        ids.append(body.id)
        x.append(_vector(body.state.pos))
        m.append(float(body.state.mass))
        r.append(float(body.shape.radius))
        fixed.append((not body.dynamic) or all_blocked)
        inertia.append(float(body.state.inertia[0]))
        v.append(_vector(body.state.vel))
    if not ids:
        raise invalid(FUNCTION, "O.bodies", "no spheres")
    return rows, ids, np.array(x), np.array(m), np.array(r), np.array(fixed), np.array(inertia), np.array(v)


def _cell(O):
    if not O.periodic:
        return None
    h = np.array([[float(O.cell.hSize[i][j]) for j in range(3)] for i in range(3)])
    if np.any(h != np.diag(np.diag(h))):
        raise invalid(FUNCTION, "O.cell.hSize", "a sheared or rotated cell is not supported (orthorhombic only)")
    return np.diag(h)


def _nearest_image(d, size):
    return d if size is None else d - size * np.round(d / size)


def read(O):
    """A demstep Scene of Yade's ``O``, and the Yade body id of each of its particles.

    Returns ``(scene, body_ids)``; ``body_ids[k]`` is the Yade id of particle k
    (the fixed twins of wall contacts come last, with the id of their sphere).
    The caller owns the scene (``with`` or ``scene.free()``).
    """
    rows, ids, x, m, r, fixed, inertia, v = _read_bodies(O)
    size = _cell(O)
    pairs, k, twins = [], [], []
    dashpots = False
    for i in O.interactions:
        if not i.isReal:
            continue
        phys, geom = i.phys, i.geom
        dashpots = dashpots or any(float(getattr(phys, name, 0.0)) != 0.0 for name in ("cn", "cs", "kr", "ktw"))
        kn, ks = float(phys.kn), float(phys.ks)
        normal = np.array(_vector(geom.normal))  # from id1 to id2
        a, b = rows.get(i.id1), rows.get(i.id2)
        if a is not None and b is not None:
            d = _nearest_image(x[b] - x[a], size)
            if float(np.dot(d, normal)) < (1.0 - 1.0e-6) * float(np.linalg.norm(d)):
                raise invalid(FUNCTION, "O.interactions", f"the contact of bodies {i.id1} and {i.id2} is not "
                              "along the nearest periodic image of their positions")
            pairs.append((a, b))
        elif a is not None or b is not None:
            sphere = a if a is not None else b
            into = normal if b is not None else -normal  # from the wall to the sphere
            depth = float(geom.penetrationDepth)
            twin = x[sphere] - into * (2.0 * r[sphere] - depth)
            twins.append((sphere, twin))
            pairs.append((sphere, len(ids) + len(twins) - 1))
        else:
            continue  # two non-spheres (facet on facet): no dof
        k.append((kn, ks))
    if dashpots:
        warnings.warn("demstep.yade: some contacts have dashpots or rolling/twisting springs, which the C "
                      "API takes for the whole scene only: the result is the undamped limit of kn, ks",
                      UserWarning, stacklevel=3)
    if twins:
        s = np.array([t[0] for t in twins])
        x = np.vstack([x, [t[1] for t in twins]])
        m, r, inertia = np.append(m, m[s]), np.append(r, r[s]), np.append(inertia, inertia[s])
        fixed = np.append(fixed, np.ones(len(twins), dtype=bool))
        v = np.vstack([v, np.zeros((len(twins), 3))])
        ids = ids + [ids[t] for t in s]
    scene = Scene(3)
    try:
        scene.set_particles(x, m, r, fixed=fixed, inertia=inertia, velocity=v)
        if size is not None:
            scene.set_cell([1, 1, 1], [0.0, 0.0, 0.0], size)
        if pairs:
            scene.set_contacts(pairs, k)
        scene.set_effects({"contacts", "rotation"})
    except BaseException:
        scene.free()
        raise
    return scene, ids


def critical_steps(O, **compute_options):
    """The critical steps of Yade's ``O`` (a SceneResult); options as Scene.compute."""
    scene, _ = read(O)
    with scene:
        return scene.compute(**compute_options)
