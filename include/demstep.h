/* demstep: time step and contact stiffness for Discrete Element Method codes.
 *
 * C API of the Fortran library (module demstep_capi). Every function returns a
 * status: DEMSTEP_OK (0) on success, one of the codes below otherwise. When the
 * last argument `err` is not NULL it receives the code and a message naming what
 * is wrong. Every input is validated as the namelist app validates it, and no
 * function returns DEMSTEP_OK with a NaN or infinite output: such a result is
 * reported as DEMSTEP_INVALID_INPUT instead. Outputs must not be NULL; arrays come with their lengths; particle
 * and bond numbers are 0-based. Link with -ldemstep -larpack -llapack -lblas -lgfortran -lgomp -lm
 * (a static libdemstep needs all of them, a shared one only -ldemstep; or use
 * pkg-config --libs [--static] demstep, or CMake target demstep::demstep).
 */
#ifndef DEMSTEP_H
#define DEMSTEP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes (demstep_stat in Fortran). */
enum {
  DEMSTEP_OK = 0,             /* success */
  DEMSTEP_INVALID_INPUT = 1,  /* an argument is out of its domain, NULL, NaN */
  DEMSTEP_UNSTABLE = 2,       /* dt at or beyond the stability limit */
  DEMSTEP_POLE = 3,           /* a denominator vanished (pole of E) */
  DEMSTEP_NOT_CONVERGED = 4,  /* an iteration did not reach its tolerance */
  DEMSTEP_NOT_FOUND = 5,      /* nothing satisfies the request */
  DEMSTEP_LAPACK_FAILURE = 6, /* LAPACK reported failure */
  DEMSTEP_IO_ERROR = 7,       /* reading or writing a file failed */
  DEMSTEP_BLOW_UP = 8,        /* a simulated value grew without bound */
  DEMSTEP_AT_STABILITY_LIMIT = 9, /* the tolerance already holds at the stability limit */
  DEMSTEP_DISCONTINUOUS = 10, /* a sign change or pick lies on a jump or pole, not a root */
  DEMSTEP_EIGENSOLVER_FAILURE = 11, /* the eigensolver (ARPACK) failed */
  DEMSTEP_BUSY = 12                /* another thread's Lanczos solve is running: call again */
};

/* Dashpots, step policies, picks, aggregation rules, contact laws, effects. */
enum { DEMSTEP_DASHPOT_LAGGED = 1, DEMSTEP_DASHPOT_CENTRED = 2 };
enum { DEMSTEP_STEPS_FIXED = 1, DEMSTEP_STEPS_FRACTION = 2, DEMSTEP_STEPS_ROUNDED = 3 };
enum { DEMSTEP_PICK_LARGEST_STEP = 1, DEMSTEP_PICK_ZERO = 2 };
enum {
  DEMSTEP_AGGREGATE_MEAN = 1, DEMSTEP_AGGREGATE_WEIGHTED = 2, DEMSTEP_AGGREGATE_MEDIAN = 3,
  DEMSTEP_AGGREGATE_MIN = 4, DEMSTEP_AGGREGATE_MAX = 5
};
enum { DEMSTEP_LAW_LINEAR = 1, DEMSTEP_LAW_HERTZ = 2 };
enum {
  DEMSTEP_EFFECT_CONTACTS = 1, DEMSTEP_EFFECT_GRAVITY = 2, DEMSTEP_EFFECT_DAMPING = 4,
  DEMSTEP_EFFECT_LOCAL_DAMPING = 8, DEMSTEP_EFFECT_WALLS = 16, DEMSTEP_EFFECT_ROTATION = 32
};
/* Where a Hertz contact is linearised: at its current overlap, or at the largest
   overlap of an impact at impact_velocity (demstep_scene_compute). */
enum { DEMSTEP_HERTZ_CURRENT = 1, DEMSTEP_HERTZ_IMPACT = 2 };
/* The DEM codes' conventions of demstep_scene_set_materials. */
enum {
  DEMSTEP_CODE_LIGGGHTS_HOOKE = 1, DEMSTEP_CODE_LIGGGHTS_HERTZ = 2, DEMSTEP_CODE_YADE_FRICTPHYS = 3,
  DEMSTEP_CODE_YADE_VISCELPHYS = 4, DEMSTEP_CODE_MFIX_LSD = 5, DEMSTEP_CODE_MFIX_HERTZIAN = 6,
  DEMSTEP_CODE_MERCURYDPM_LINEAR = 7, DEMSTEP_CODE_LAMMPS_HOOKE = 8, DEMSTEP_CODE_LAMMPS_HERTZ_MATERIAL = 9
};

/* The DEM codes' bond models of demstep_scene_set_bond_model. */
enum { DEMSTEP_BOND_PFC = 1, DEMSTEP_BOND_MUSEN = 2, DEMSTEP_BOND_YADE = 3, DEMSTEP_BOND_LAMMPS = 4 };

/* Eigensolvers for omega_max (demstep_scene_set_eigen_solver): AUTO takes DENSE
   (LAPACK) up to max_eigen_dof and LANCZOS (ARPACK, matrix-free) above; NONE
   gives the bound only. */
enum { DEMSTEP_EIGEN_AUTO = 1, DEMSTEP_EIGEN_DENSE = 2, DEMSTEP_EIGEN_LANCZOS = 3,
       DEMSTEP_EIGEN_NONE = 4 };

/* A status, its message and the location of the fault (NUL-terminated texts).
   `where` names the argument or field to change ("" when no single one);
   `index` is its 0-based element or row, -1 when none applies. */
typedef struct {
  int stat;
  char message[256];
  char where[64];
  int index;
} demstep_error;

/* A mass on a linear spring with a viscous dashpot c = 2 zeta sqrt(K M). */
typedef struct {
  double mass, stiffness, damping;
  int compression_only; /* 1: a contact (force only while x > 0); 0: a bond */
  int dashpot;          /* DEMSTEP_DASHPOT_LAGGED or DEMSTEP_DASHPOT_CENTRED */
} demstep_spring;

/* Overlap x_n (positive in compression), half-step velocity v_n, steps taken. */
typedef struct {
  double x, v;
  int64_t step;
} demstep_spring_state;

/* One lambda's scan: pick, smallest root of E, first interval |E| <= E0. */
typedef struct {
  double n_pick, n_zero, n_lower, n_upper; /* 0 where there is none */
  int interval;    /* kind of the first interval [n_lower, n_upper]: 0 bounded (closed
                      below n_max), 1 unbounded (|E| <= E0 for every larger N), 2 truncated
                      (cut at n_max, ends beyond it) */
  int stat;        /* DEMSTEP_OK, DEMSTEP_AT_STABILITY_LIMIT (the tolerance holds at the
                      stability limit: n_pick is there) or DEMSTEP_NOT_FOUND (none) */
  int evaluations; /* evaluations of E */
} demstep_nroots;

/* The simulated-stiffness procedure's answer: dt = T* / N*, K' = lambda*^2 K*. */
typedef struct {
  double n_star, lambda_star, period, dt, stiffness_actual;
  int lambda_star_stat; /* DEMSTEP_OK, DEMSTEP_DISCONTINUOUS (the pick jumps at lambda*)
                           or DEMSTEP_NOT_FOUND (N* outside the picks of the set) */
  int excluded;         /* lambdas without an admissible N */
} demstep_stiffness_result;

/* The exact discrete contact at N = T/dt and onset s in (0, 1] (lagged dashpot with
   damping_ratio); contact time in T/2, overlap in v0/omega, restitution -v_out/v0. */
typedef struct {
  double onset, contact_time, restitution, max_overlap;
  int64_t steps; /* force evaluations with a positive overlap */
  int stable;    /* 0 beyond the stability limit (computed by exact stepping) */
} demstep_contact;

/* Quantities for demstep_n_for_tolerance. */
enum {
  DEMSTEP_QUANTITY_RESTITUTION = 1, DEMSTEP_QUANTITY_CONTACT_TIME = 2,
  DEMSTEP_QUANTITY_OVERLAP = 3, DEMSTEP_QUANTITY_PERIOD = 4
};

/* Build a validated spring (mass, stiffness > 0; damping_ratio >= 0). */
int demstep_spring_new(double mass, double stiffness, double damping_ratio, int compression_only,
                       int dashpot, demstep_spring *spring, demstep_error *err);

/* One central-difference step: x += v dt, then v += F/M dt. */
int demstep_spring_step(const demstep_spring *spring, double dt, demstep_spring_state *state,
                        demstep_error *err);

/* The largest stable step: 2 sqrt(M/K), times sqrt(1 + z^2) - z with a lagged dashpot. */
int demstep_critical_time_step(const demstep_spring *spring, double *dt_critical,
                               demstep_error *err);

/* The paper's error E(N, lambda, n); DEMSTEP_POLE where S(2 pi lambda/N, n) = 0. */
int demstep_harmonic_error(double n_per_period, double lambda, double n_steps, double *e,
                           demstep_error *err);

/* Roots and admissible N of E for one lambda: the scan splits at E's poles and stops at
   the first root and the first interval. n_max, resolution <= 0: defaults (1e8, 0.5);
   NaN, tolerance outside [1e-10, 1), n_max beyond what the step policy can evaluate
   (n = f N <= 1e12) and a scan over 2e7 evaluations of E: DEMSTEP_INVALID_INPUT. */
int demstep_n_roots(double lambda, double tolerance, int steps_kind, double steps_value, int pick,
                    double n_max, double resolution, demstep_nroots *result, demstep_error *err);

/* The whole procedure for n_lambdas increasing lambdas in (0, 1); weights may be NULL
   (unless DEMSTEP_AGGREGATE_WEIGHTED); n_pick and row_status (n_lambdas each) may be NULL. */
int demstep_simulated_stiffness(double mass, double stiffness, double tolerance,
                                const double *lambdas, int n_lambdas, int steps_kind,
                                double steps_value, int pick, int aggregate,
                                const double *weights, double *n_pick, int *row_status,
                                demstep_stiffness_result *result, demstep_error *err);

/* ---- Scenes: an opaque handle built call by call ----
 *
 *   demstep_scene *s = NULL;
 *   demstep_scene_create(3, &s, &err);
 *   demstep_scene_set_particles(s, n, x, mass, radius, NULL, NULL, NULL, &err);
 *   demstep_scene_set_contact_law(s, DEMSTEP_LAW_LINEAR, 1.0e5, 0.0, &err);
 *   demstep_scene_compute(s, DEMSTEP_HERTZ_CURRENT, 0.0, 0, 0, &res, sizeof res, &err);
 *   demstep_scene_free(&s, &err);    (s is NULL again: a second free does nothing)
 *
 * The particles are set once, before the cell, bonds, per-type materials, walls
 * and an explicit contact list; the stiffnesses, law, effects, damping and
 * gravity may be set at any time (a later call replaces them). Each call validates its arguments with the library's own rules. When a call
 * that builds the scene fails, the scene is unusable: every later call on it but
 * demstep_scene_free returns DEMSTEP_INVALID_INPUT quoting that first failure
 * (free it and build it again). demstep_scene_compute does not change the scene:
 * it may be called again with other options. Particle, bond, type and contact
 * numbers passed in are 0-based; messages count particles, bonds, rows and types
 * from 1. A scene handle must not be used by two threads at once. */
typedef struct demstep_scene demstep_scene;

/* Critical time steps of a scene (undamped central differences: 2/omega).
   Fields are only ever appended in later versions: pass sizeof(demstep_scene_result)
   as result_size, and a program built against an older header gets the fields
   it knows. */
typedef struct {
  double omega_max, dt_critical_eigen;   /* exact (LAPACK); 0 unless eigen_computed */
  double omega_bound, dt_critical_bound; /* Gershgorin bound: dt_bound <= exact */
  double dt_contact_rule;                /* min 2 sqrt(m* / k): NOT safe */
  double damping_ratio_top;   /* modal damping ratio of the top mode (the scene's
                                 damping ratio when eigen_computed is 0) */
  double dt_critical_damped;  /* the lagged-dashpot limit (from the bound when
                                 eigen_computed is 0) */
  int n_dof;                  /* free particles times dof_per_particle */
  int n_springs;              /* bonds + particle contacts + wall contacts */
  int dof_per_particle;       /* dim translations (+ rotations with DEMSTEP_EFFECT_ROTATION) */
  int eigen_computed;         /* 1: an eigensolver ran, the exact fields are set */
  int rotation, tangential, periodic, prestress; /* 1: the model counted them */
  /* appended in version 2: the eigensolver's report */
  double eigen_tolerance;     /* relative tolerance (dense: the working precision) */
  double eigen_residual;      /* measured ||A z - theta z|| / theta of the top mode */
  double omega_upper;         /* upper end of omega_max's error bar */
  double dt_critical_safe;    /* max(2/omega_upper, the bound): safe to the error bar */
  int64_t eigen_products;     /* Lanczos operator products */
  int eigen_solver;           /* which ran: DEMSTEP_EIGEN_DENSE, _LANCZOS or _NONE */
  int eigen_converged;        /* 0: Lanczos ran out of restarts; omega_max is then in
                                 [omega_max, omega_upper] */
  /* appended in version 3: the exact damped limit (dt_critical_damped is the
     smallest h with lambda_max(h^2 A + 2 h B) = 4, verified below it) */
  double dt_critical_damped_bound; /* its rigorous lower bound */
  int damped_exact;           /* 1: dt_critical_damped is the exact limit; 0: the bound */
  int damped_solves;          /* eigensolves of its Newton steps */
} demstep_scene_result;

/* A scene without particles in dim (1 to 3) dimensions; *scene receives the handle
   (NULL on failure). */
int demstep_scene_create(int dim, demstep_scene **scene, demstep_error *err);

/* Free the scene *scene and set *scene to NULL; scene == NULL or *scene == NULL:
   nothing to do (DEMSTEP_OK). Copies of the handle are dangling afterwards. */
int demstep_scene_free(demstep_scene **scene, demstep_error *err);

/* The n particles (once per scene): x holds dim coordinates per particle; fixed (n
   flags), inertia (n moments, default 2/5 m r^2) and velocity (dim per particle,
   default 0) may be NULL. */
int demstep_scene_set_particles(demstep_scene *scene, int n, const double *x, const double *mass,
                                const double *radius, const int *fixed, const double *inertia,
                                const double *velocity, demstep_error *err);

/* Bonds: 2 particle numbers per bond; rest vectors from the current positions
   (through the nearest periodic image: set a cell first). Their stiffness is
   demstep_scene_set_bond_stiffness's. */
int demstep_scene_add_bonds(demstep_scene *scene, int n_bonds, const int *bonds, demstep_error *err);

/* Every bond's normal (> 0) and tangential (>= 0) stiffness. */
int demstep_scene_set_bond_stiffness(demstep_scene *scene, double k_bond, double k_bond_tangential,
                                     demstep_error *err);

/* Every bond's law as a DEM code makes it, from that code's own n_parameters
   inputs in its order: DEMSTEP_BOND_PFC (parallel bond: kbar_n, kbar_s, lambda),
   DEMSTEP_BOND_MUSEN (solid bond: E, G, diameter), DEMSTEP_BOND_YADE
   (CohFrictPhys: young, poisson, alpha_kr, alpha_ktw) or DEMSTEP_BOND_LAMMPS
   (bpm/rotational: K_r, K_s, K_t, K_b, gamma_n, gamma_s, gamma_r, gamma_t):
   normal, shear, bending and twisting springs (LAMMPS: and its dashpots), instead
   of demstep_scene_set_bond_stiffness's; rotations come on. A value out of range
   is refused naming it (where "bond_parameters", index 0-based). */
int demstep_scene_set_bond_model(demstep_scene *scene, int model, int n_parameters,
                                 const double *parameters, demstep_error *err);

/* Rigid bodies (clumps, multispheres) of the particles, once per scene, after
   demstep_scene_set_particles: body_of holds a body id per particle (0: a
   particle on its own; any positive ids, the bodies numbered in increasing id).
   mass NULL: each body's mass and inertia tensor from its members (Yade's sum:
   overlaps counted twice; density > 0: the members' masses rho 4/3 pi r^3, else
   the particles' own); otherwise n_bodies bodies, ids 1..n_bodies, with mass
   (n_bodies), com (3 per body) and inertia (9 per body: the symmetric tensor about
   the centre of mass, global axes) as given. demstep_scene_compute then gives the
   bodies' limits (dof_per_particle is per body), with DEMSTEP_HERTZ_CURRENT and
   prestress 0 only. */
int demstep_scene_set_bodies(demstep_scene *scene, const int *body_of, double density, int n_bodies,
                             const double *mass, const double *com, const double *inertia,
                             demstep_error *err);

/* The peers' rules on the scene's bodies, raw: Yade's GlobalStiffnessTimeStepper
   (safety coefficient 1) and exaDEM's pi sqrt(m_min / k_n,max). */
int demstep_scene_body_peer_steps(const demstep_scene *scene, double *yade_gst, double *exadem,
                                  demstep_error *err);

/* The contact law of particle and wall contacts: DEMSTEP_LAW_LINEAR with normal = k_n
   (> 0), tangential = k_t (>= 0); DEMSTEP_LAW_HERTZ with normal = E* (> 0),
   tangential = Mindlin's G* (>= 0). Default: linear, no stiffness. */
int demstep_scene_set_contact_law(demstep_scene *scene, int law, double normal, double tangential,
                                  demstep_error *err);

/* Linear materials per particle type: types (n, 0 to n_types - 1), k_normal and
   k_tangential (n_types x n_types, symmetric; k_tangential may be NULL: 0). They
   replace the law's k_n, k_t for particle contacts; the law becomes linear (a Hertz
   law set before is refused). */
int demstep_scene_set_types(demstep_scene *scene, int n_types, const int *types,
                            const double *k_normal, const double *k_tangential, demstep_error *err);

/* Hertz materials per particle type: Young's modulus (> 0) and Poisson's ratio
   (-1, 0.5] per type; E* and G* of each pair follow; the law becomes Hertz. */
int demstep_scene_set_hertz_types(demstep_scene *scene, int n_types, const int *types,
                                  const double *young, const double *poisson, demstep_error *err);

/* Materials per type (types 0-based, n_types of each array: Young's modulus,
   Poisson's ratio, density, nominal radius) in one code's convention
   (DEMSTEP_CODE_...) with its restitution and impact velocity: the law, each
   pair's springs and dashpots, and the walls as contacts of type wall_type
   (-1: each particle's own), as the code computes them; tangential_damping 1
   keeps the code's tangential dashpots (LIGGGHTS' default), 0 drops them. */
int demstep_scene_set_materials(demstep_scene *scene, int n_types, const int *types,
                                const double *young, const double *poisson, const double *density,
                                const double *radius, int convention, double restitution,
                                double impact_velocity, int wall_type, int tangential_damping,
                                demstep_error *err);

/* Walls: per wall a point and a normal into the domain, dim values each. */
int demstep_scene_add_walls(demstep_scene *scene, int n_walls, const double *points,
                            const double *normals, demstep_error *err);

/* An explicit contact list instead of detection: pairs (2 particle numbers per
   contact) and k (k_n > 0, k_t >= 0 per contact, linear). */
int demstep_scene_set_contacts(demstep_scene *scene, int n_contacts, const int *pairs,
                               const double *k, demstep_error *err);

/* The effects switched on: a sum of DEMSTEP_EFFECT_* flags (0: none; default
   DEMSTEP_EFFECT_CONTACTS); any other bit is refused, naming the known flags.
   Rotations count only with DEMSTEP_EFFECT_ROTATION (tangential springs do not
   switch it on). */
int demstep_scene_set_effects(demstep_scene *scene, int effects, demstep_error *err);

/* A periodic orthorhombic cell [lo, hi): periodic, lo and hi hold dim values
   (periodic: nonzero for a periodic axis); positions are wrapped into the cell. */
int demstep_scene_set_cell(demstep_scene *scene, const int *periodic, const double *lo,
                           const double *hi, demstep_error *err);

/* The viscous damping ratio of DEMSTEP_EFFECT_DAMPING, 0 to 1e100 (checked
   here; NaN is refused): normal dashpots c_n = 2 zeta sqrt(m* k_n) and
   tangential ones c_t = 2 zeta sqrt(m* k_t), as LIGGGHTS' tangential_damping
   on. The effect itself is switched by demstep_scene_set_effects. */
int demstep_scene_set_damping(demstep_scene *scene, double damping_ratio, demstep_error *err);

/* The other dashpots of DEMSTEP_EFFECT_DAMPING: the tangential damping ratio
   (c_t = 2 zeta_t sqrt(m* k_t); demstep_scene_set_damping sets it to the normal
   ratio), the rolling and twisting one (c = 2 zeta_r sqrt(I* k)), each 0 to 1e100,
   and a drag to the ground F = -drag v (>= 0). */
int demstep_scene_set_dashpots(demstep_scene *scene, double tangential, double rolling, double drag,
                               demstep_error *err);

/* Rolling and twisting springs: k_r = rolling_ratio k_t R*^2, k_w = twisting_ratio
   k_t R*^2 (each >= 0; LIGGGHTS epsd2 is rolling_ratio 1); rotations come on. */
int demstep_scene_set_rolling(demstep_scene *scene, double rolling_ratio, double twisting_ratio,
                              demstep_error *err);

/* The gravity vector of DEMSTEP_EFFECT_GRAVITY: dim finite components. */
int demstep_scene_set_gravity(demstep_scene *scene, const double *gravity, demstep_error *err);

/* The critical steps of the scene at its current configuration. hertz_linearization:
   DEMSTEP_HERTZ_CURRENT or DEMSTEP_HERTZ_IMPACT (with impact_velocity > 0; ignored
   otherwise); prestress: 0 or 1 (count the geometric stiffness of loaded contacts);
   max_eigen_dof: under DEMSTEP_EIGEN_AUTO, dense LAPACK up to it and Lanczos above (<= 0: the default 1000);
   result_size: sizeof(demstep_scene_result). */
/* The eigensolver of later demstep_scene_compute calls (default DEMSTEP_EIGEN_AUTO)
   and the Lanczos relative residual tolerance, in [2.2e-16, 0.1] (<= 0: the default 1e-6). */
int demstep_scene_set_eigen_solver(demstep_scene *scene, int solver, double tolerance,
                                   demstep_error *err);

int demstep_scene_compute(const demstep_scene *scene, int hertz_linearization,
                          double impact_velocity, int prestress, int max_eigen_dof,
                          demstep_scene_result *result, size_t result_size, demstep_error *err);

/* ---- Inside a DEM solver: its own arrays, no scene, no contact search ----
 *
 * The critical steps of dim-D particles (x: dim values per particle, n of them;
 * mass, radius; inertia NULL: 2/5 m r^2) and the solver's contact list: pairs
 * (2 per contact, 0-based particle numbers) with k_n, k_t, c_n, c_t (each
 * n_values long: 1, every contact the same, or n_contacts; NULL k_t, c_n, c_t:
 * none). A listed pair acts while it overlaps, through the nearest periodic
 * image. Walls: n_walls points and normals (dim values each) with wall_k =
 * {k_n, k_t} and wall_damping = {zeta_n, zeta_t} (NULL: undamped). periodic:
 * dim flags with the cell [cell_lo, cell_hi) (NULL: no periodic axis).
 * Rotations are on when any k_t (or the walls' k_t) is > 0. solver:
 * DEMSTEP_EIGEN_*; tolerance <= 0: the default 1e-6. The arrays are read in place. */
int demstep_solver_compute(int dim, int n, const double *x, const double *mass,
                           const double *radius, const double *inertia, int n_contacts,
                           const int *pairs, int n_values, const double *k_n, const double *k_t,
                           const double *c_n, const double *c_t, int n_walls,
                           const double *wall_point, const double *wall_normal,
                           const double *wall_k, const double *wall_damping, const int *periodic,
                           const double *cell_lo, const double *cell_hi, int solver,
                           double tolerance, demstep_scene_result *result, size_t result_size,
                           demstep_error *err);

/* The same solve (result filled as by demstep_solver_compute) and which particles
 * and contacts carry its top undamped mode: particle_share (n values: each
 * particle's squared amplitude, 0 for none), contact_share (n_contacts: each
 * listed contact's part of the mode's energy, 0 when it does not overlap; NULL
 * allowed when n_contacts is 0) and wall_share (n: each particle's wall contacts,
 * summed). particle_share sums to 1, and so do contact_share and wall_share
 * together. DEMSTEP_INVALID_INPUT for NULL shares or with DEMSTEP_EIGEN_NONE. */
int demstep_solver_participation(int dim, int n, const double *x, const double *mass,
                                 const double *radius, const double *inertia, int n_contacts,
                                 const int *pairs, int n_values, const double *k_n,
                                 const double *k_t, const double *c_n, const double *c_t,
                                 int n_walls, const double *wall_point, const double *wall_normal,
                                 const double *wall_k, const double *wall_damping,
                                 const int *periodic, const double *cell_lo, const double *cell_hi,
                                 int solver, double tolerance, demstep_scene_result *result,
                                 size_t result_size, double *particle_share, double *contact_share,
                                 double *wall_share, demstep_error *err);

/* The discrete contact at one onset. */
int demstep_contact_with_onset(double n_per_period, double onset, double damping_ratio,
                               demstep_contact *contact, demstep_error *err);

/* The smallest N = T/dt whose worst-case (over the onset) error of a quantity stays
   within tolerance at N and above; n_max <= 0 means 1e7. DEMSTEP_NOT_FOUND if not met. */
int demstep_n_for_tolerance(int quantity, double tolerance, double damping_ratio, double n_max,
                            double *n, demstep_error *err);

/* ---- Snapshots: the particles of a DEM code's file (appended) ----
 *
 *   demstep_snapshot *snap = NULL;
 *   demstep_snapshot_info info;
 *   demstep_snapshot_read("dump.liggghts", DEMSTEP_SNAPSHOT_AUTO, 0, 0, NULL, &snap, &info, &err);
 *   demstep_snapshot_get(snap, NULL, types, x, NULL, NULL, radius, mass, NULL, &err);
 *   demstep_snapshot_free(&snap, &err);
 *
 * The library's snapshot readers: LAMMPS/LIGGGHTS dumps and data files (atom
 * style sphere) and Yade's text export, each refused in one line naming the
 * file and the line (DEMSTEP_IO_ERROR for a file that cannot be read). */
enum { DEMSTEP_SNAPSHOT_AUTO = 0, DEMSTEP_SNAPSHOT_LAMMPS_DUMP = 1, DEMSTEP_SNAPSHOT_LAMMPS_DATA = 2,
       DEMSTEP_SNAPSHOT_YADE_TEXT = 3 };

typedef struct demstep_snapshot demstep_snapshot;

/* What a snapshot holds: n particles, the format read, the dump's frame (1-based)
   of n_frames and its timestep; flags (1: present) for velocities, angular
   velocities, masses, densities and the box; periodic axes; box bounds (0 when
   has_box is 0: Yade writes none). */
typedef struct {
  int n, format, frame, n_frames;
  int64_t timestep;
  int has_velocity, has_omega, has_mass, has_density, has_box;
  int periodic[3];
  double lo[3], hi[3];
} demstep_snapshot_info;

/* Read path (NUL-terminated) in format (DEMSTEP_SNAPSHOT_AUTO: detected); frame:
   a dump's frame, 1-based, 0 the last, negative from the end; type_density
   (n_types densities, or n_types = 0 and NULL): masses from a density per type
   when the file has none. *snapshot receives the handle (NULL on failure). */
int demstep_snapshot_read(const char *path, int format, int frame, int n_types,
                          const double *type_density, demstep_snapshot **snapshot,
                          demstep_snapshot_info *info, demstep_error *err);

/* Copy the snapshot's arrays: n values each, 3 per particle for x, v and omega
   (zeros where the file had none); any may be NULL (not copied). Types are
   0-based (the file's type minus 1; Yade's matId). */
int demstep_snapshot_get(const demstep_snapshot *snapshot, int64_t *id, int *type, double *x,
                         double *v, double *omega, double *radius, double *mass, double *density,
                         demstep_error *err);

/* Free the snapshot *snapshot and set *snapshot to NULL (NULL: nothing to do). */
int demstep_snapshot_free(demstep_snapshot **snapshot, demstep_error *err);

/* ---- Materials of a pair and the peers' rules (appended) ---- */

/* One particle type: Young's modulus (> 0), Poisson's ratio (-1, 0.5], density and radius (> 0). */
typedef struct {
  double young, poisson, density, radius;
} demstep_material;

/* A contact between types a and b and its loading: normal restitution (0, 1];
   tangential restitution (0: the normal one); impact velocity (> 0); the
   collision time of the codes set from one (0: the Hertz duration); the linear
   stiffness of the codes that take one (0: LIGGGHTS' Hooke stiffness). */
typedef struct {
  demstep_material a, b;
  double restitution, restitution_t, impact_velocity, contact_time, stiffness;
} demstep_material_pair;

/* A pair's contact in one code's convention: springs and dashpots (Hertz
   conventions: secant values at `overlap`, the largest overlap of the impact),
   the contact duration, the collision time the code computes (0: none), m* and
   the exact stability limit of the contact as the code steps it. */
typedef struct {
  double k_n, k_t, gamma_n, gamma_t, overlap, t_contact, code_collision_time, m_star, dt_code;
} demstep_code_contact;

/* The peers' rules of thumb, indices of demstep_peer_steps.dt (0-based: rule - 1). */
enum {
  DEMSTEP_PEER_EDEM_RAYLEIGH_20 = 1, DEMSTEP_PEER_EDEM_RAYLEIGH_40 = 2,
  DEMSTEP_PEER_LIGGGHTS_RAYLEIGH_10 = 3, DEMSTEP_PEER_LIGGGHTS_HERTZ_10 = 4,
  DEMSTEP_PEER_MFIX_LSD_TC50 = 5, DEMSTEP_PEER_MFIX_HERTZIAN_TC50 = 6,
  DEMSTEP_PEER_MERCURYDPM_TC50 = 7, DEMSTEP_PEER_YADE_PWAVE = 8, DEMSTEP_PEER_YADE_PWAVE_30 = 9
};

/* A pair's time scales (Rayleigh time with LIGGGHTS'/EDEM's and with Yade's
   constant, the Hertz duration at the impact velocity, LIGGGHTS' Hertz time)
   and the step each peer's rule picks (dt[DEMSTEP_PEER_... - 1]). */
typedef struct {
  double rayleigh, rayleigh_yade, hertz_duration, hertz_liggghts;
  double dt[9];
} demstep_peer_steps;

/* The contact of a pair in convention (DEMSTEP_CODE_...), as the &material report. */
int demstep_contact_parameters(const demstep_material_pair *pair, int convention,
                               demstep_code_contact *params, demstep_error *err);

/* The pair's time scales and the peers' rules, as the &material report. */
int demstep_peer_time_steps(const demstep_material_pair *pair, demstep_peer_steps *steps,
                            demstep_error *err);

#ifdef __cplusplus
}
#endif

#endif /* DEMSTEP_H */
