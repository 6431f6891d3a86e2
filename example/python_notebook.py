# %% [markdown]
# # demstep from Python, notebook style
#
# Cells (`# %%`) for Jupyter (jupytext), VS Code or Spyder; or run it whole:
# `.venv/bin/python example/python_notebook.py` after the README's "From Python"
# install. Every number printed is computed here; the data are the repository's
# validation scenes.

# %%
from pathlib import Path

import numpy as np

import demstep

root = Path(__file__).resolve().parents[1] if "__file__" in globals() else Path.cwd()

# %% [markdown]
# ## One contact spring
# The critical step of a mass on a spring, and the simulated-stiffness procedure:
# from a tolerance on the error E to the step dt and the softened stiffness K'.

# %%
spring = demstep.Spring(mass=0.01, stiffness=1.0e5)
print("critical step of the spring:", spring.critical_time_step(), "s")
lambdas = np.linspace(0.9, 0.99, 10)
procedure = demstep.simulated_stiffness(0.01, 1.0e5, 1.0e-3, lambdas)
print(f"tolerance 1e-3: dt = {procedure.dt:.6e} s with K' = {procedure.stiffness_actual:.6e} N/m "
      f"(N* = {procedure.n_star:.4f})")

# %% [markdown]
# ## A periodic assembly from arrays: Yade's simple cubic lattice
# 216 spheres and the 648 contacts Yade integrated (validation/yade/data/sc),
# rotations on. Yade's measured largest stable step is in summary.json.

# %%
import json

data = root / "validation/yade/data/sc"
p = np.loadtxt(data / "particles.txt")          # x y z vx vy vz mass radius fixed inertia
contacts = np.loadtxt(data / "contacts.txt")    # i j k_n k_t (1-based)
cell = json.loads((data / "cell.json").read_text())
with demstep.Scene(3) as scene:
    scene.set_particles(p[:, 0:3], p[:, 6], p[:, 7], inertia=p[:, 9])
    scene.set_contacts(contacts[:, :2].astype(int) - 1, contacts[:, 2:4])
    scene.set_cell(cell["periodic"], cell["cell_lo"], cell["cell_hi"])
    scene.set_effects({"contacts", "rotation"})
    sc = scene.compute()
measured = json.loads((data / "summary.json").read_text())
print(f"demstep exact limit {sc.dt_critical_eigen:.6e} s ({sc.eigen_solver=}, {sc.n_dof} dof); "
      f"Yade measured [{measured['measured_dt_lo']:.6e}, {measured['measured_dt_hi']:.6e}] s; "
      f"ratio {sc.dt_critical_eigen / measured['measured_dt_lo']:.5f}")

# %% [markdown]
# ## A LIGGGHTS pile with materials in LIGGGHTS' convention
# 729 spheres of 3 types from a LIGGGHTS dump in a box of 6 walls; Hertz with the
# dashpots of restitution 0.5 (validation/liggghts/demstep/a_hertz.nml gives the
# app the same scene).

# %%
rows = np.loadtxt(root / "validation/liggghts/demstep/a_hertz.dump", skiprows=9)
walls = np.array([[-0.01, 0, 0, 1, 0, 0], [0.01, 0, 0, -1, 0, 0], [0, -0.01, 0, 0, 1, 0],
                  [0, 0.01, 0, 0, -1, 0], [0, 0, 0, 0, 0, 1], [0, 0, 0.05, 0, 0, -1]], dtype=float)
with demstep.Scene(3) as scene:
    scene.set_particles(rows[:, 2:5], rows[:, 9], rows[:, 8], velocity=rows[:, 5:8])
    scene.set_materials(rows[:, 1].astype(int) - 1, young=[1.0e7] * 3, poisson=[0.3] * 3,
                        density=[2500.0] * 3, radius=[0.001, 0.00125, 0.0015], code="liggghts_hertz",
                        restitution=0.5, impact_velocity=1.0, wall_type=0)
    scene.add_walls(walls[:, :3], walls[:, 3:])
    scene.set_effects(["contacts", "rotation", "walls", "damping"])
    pile = scene.compute()
print(f"undamped {pile.dt_critical_eigen:.6e} s, with the dashpots {pile.dt_critical_damped:.6e} s "
      f"(exact: {bool(pile.damped_exact)}), per-contact rule {pile.dt_contact_rule:.6e} s")

# %% [markdown]
# ## Materials and the peers' rules
# Glass beads (E = 63 GPa, 1 mm diameter, e = 0.9, 1 m/s): the contact as each code
# computes it, its exact limit as that code steps it, and what the rules of thumb pick.

# %%
glass = demstep.Material(young=6.3e10, poisson=0.22, density=2500.0, radius=0.5e-3)
for code in ("liggghts_hertz", "yade_frictphys", "mfix_lsd"):
    c = demstep.contact_parameters(glass, glass, code, restitution=0.9, impact_velocity=1.0)
    print(f"{code:15s} k_n = {c.k_n:.4e} N/m, exact limit as {code} steps it {c.dt_code:.4e} s")
exact = demstep.contact_parameters(glass, glass, "liggghts_hertz", 0.9, 1.0).dt_code
for rule, dt in demstep.peer_time_steps(glass, glass, 0.9, 1.0).dt.items():
    print(f"{rule:22s} {dt:.4e} s = {dt / exact:.3f} of LIGGGHTS' Hertz limit")

# %% [markdown]
# ## Errors
# One exception type; the argument is named, in the library's form.

# %%
try:
    with demstep.Scene(3) as scene:
        scene.set_particles(np.zeros((4, 2)), np.ones(4), np.ones(4))
except demstep.DemstepError as e:
    print(e.code_name, "|", e.where, "|", e)
try:
    with demstep.Scene(3) as scene:
        scene.set_particles([[0, 0, 0], [np.nan, 0, 0]], [1.0, 1.0], [0.5, 0.5])
except demstep.DemstepError as e:
    print(e.code_name, "|", e)

# %% [markdown]
# ## Inside Yade
# In a Yade script (Debian's `yade`, the package on its path; see the README):
#
# ```python
# import demstep.yade
# limits = demstep.yade.critical_steps(O)
# print("exact limit", limits.dt_critical_eigen, "s; O.dt is", O.dt)
# ```
