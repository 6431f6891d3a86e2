/* A C program using demstep: a contact spring stepped in a loop, the paper's
 * error E, the simulated-stiffness procedure, the critical steps of four scenes
 * built through a scene handle (a bonded chain; a Hertz sphere on a wall; a
 * rigid two-sphere clump on a floor, with the peers' rules; a pair held by
 * Yade's cohesive bond); then bad input, which returns a status and a message. Each result is printed as
 * "name value" with 17 significant digits, for comparison with Fortran. */
#include <math.h>
#include <stdio.h>
#include "demstep.h"

static void put(const char *name, double value) { printf("%s %.16e\n", name, value); }

int main(void) {
  demstep_error err;
  demstep_spring spring;
  demstep_spring_state state = {0.0, 1.0, 0};
  double dt_crit, e;
  int i;

  if (demstep_spring_new(0.01, 1.0e5, 0.0, 1, DEMSTEP_DASHPOT_LAGGED, &spring, &err) != DEMSTEP_OK) {
    fprintf(stderr, "spring: %s\n", err.message);
    return 1;
  }
  demstep_critical_time_step(&spring, &dt_crit, &err);
  put("dt_critical", dt_crit);
  for (i = 0; i < 1000; ++i) demstep_spring_step(&spring, 0.1 * dt_crit, &state, &err);
  put("x_1000", state.x);
  put("v_1000", state.v);

  demstep_harmonic_error(19.316, 0.9, 9.658, &e, &err);
  put("e_half_period", e);
  demstep_harmonic_error(1000.0, 1.0 - 1.0e-9, 1.0e7 + 1.0, &e, &err);
  put("e_hard", e);

  {
    demstep_nroots r;
    demstep_n_roots(0.9, 1.0e-3, DEMSTEP_STEPS_FRACTION, 0.5, DEMSTEP_PICK_LARGEST_STEP, 0.0, 0.0, &r,
                    &err);
    put("n_pick", r.n_pick);
    put("n_zero", r.n_zero);
  }

  {
    double lambdas[10], picks[10];
    int row[10];
    demstep_stiffness_result res;
    for (i = 0; i < 10; ++i) lambdas[i] = 0.9 + (0.99 - 0.9) * i / 9.0;
    demstep_simulated_stiffness(0.01, 1.0e5, 1.0e-3, lambdas, 10, DEMSTEP_STEPS_FRACTION, 0.5,
                                DEMSTEP_PICK_LARGEST_STEP, DEMSTEP_AGGREGATE_MEAN, NULL, picks, row,
                                &res, &err);
    put("n_star", res.n_star);
    put("lambda_star", res.lambda_star);
    put("dt", res.dt);
    put("stiffness_actual", res.stiffness_actual);
  }

  {
    /* a 1D chain of 12 unit masses, ends fixed, bonds k = 100, no contacts */
    double x[12], m[12], r[12];
    int fixed[12] = {0}, bonds[22];
    demstep_scene *s = NULL;
    demstep_scene_result c;
    for (i = 0; i < 12; ++i) { x[i] = i + 1.0; m[i] = 1.0; r[i] = 0.3; }
    fixed[0] = fixed[11] = 1;
    for (i = 0; i < 11; ++i) { bonds[2 * i] = i; bonds[2 * i + 1] = i + 1; }
    if (demstep_scene_create(1, &s, &err) != DEMSTEP_OK ||
        demstep_scene_set_particles(s, 12, x, m, r, fixed, NULL, NULL, &err) != DEMSTEP_OK ||
        demstep_scene_add_bonds(s, 11, bonds, &err) != DEMSTEP_OK ||
        demstep_scene_set_bond_stiffness(s, 100.0, 0.0, &err) != DEMSTEP_OK ||
        demstep_scene_set_effects(s, 0, &err) != DEMSTEP_OK ||
        demstep_scene_compute(s, DEMSTEP_HERTZ_CURRENT, 0.0, 0, 0, &c, sizeof c, &err) != DEMSTEP_OK) {
      fprintf(stderr, "chain: %s\n", err.message);
      demstep_scene_free(&s, NULL);
      return 1;
    }
    put("omega_max", c.omega_max);
    put("dt_critical_bound", c.dt_critical_bound);
    put("dt_contact_rule", c.dt_contact_rule);
    demstep_scene_free(&s, &err);
    demstep_scene_free(&s, &err); /* s is NULL: nothing to do */
  }

  {
    /* a 2D sphere pressed into the floor y = 0, Hertz (E* = 1e8, G* = 4e7),
       linearised at an impact at 2 m/s, with dashpots (zeta = 0.1) */
    double x[2] = {0.0, 0.0099}, m = 0.01, r = 0.01;
    double point[2] = {0.0, 0.0}, normal[2] = {0.0, 1.0};
    demstep_scene *s = NULL;
    demstep_scene_result c;
    if (demstep_scene_create(2, &s, &err) != DEMSTEP_OK ||
        demstep_scene_set_particles(s, 1, x, &m, &r, NULL, NULL, NULL, &err) != DEMSTEP_OK ||
        demstep_scene_add_walls(s, 1, point, normal, &err) != DEMSTEP_OK ||
        demstep_scene_set_contact_law(s, DEMSTEP_LAW_HERTZ, 1.0e8, 4.0e7, &err) != DEMSTEP_OK ||
        demstep_scene_set_damping(s, 0.1, &err) != DEMSTEP_OK ||
        demstep_scene_set_effects(s, DEMSTEP_EFFECT_WALLS | DEMSTEP_EFFECT_DAMPING, &err) != DEMSTEP_OK ||
        demstep_scene_compute(s, DEMSTEP_HERTZ_IMPACT, 2.0, 0, 0, &c, sizeof c, &err) != DEMSTEP_OK) {
      fprintf(stderr, "wall: %s\n", err.message);
      demstep_scene_free(&s, NULL);
      return 1;
    }
    put("wall_omega_max", c.omega_max);
    put("wall_dt_critical_damped", c.dt_critical_damped);
    /* bad input on a scene: an unknown Hertz mode (the scene stays usable), an
       unknown effect bit (a failed builder call: the scene is unusable after it) */
    printf("bad_hertz_mode %d %s\n", demstep_scene_compute(s, 7, 0.0, 0, 0, &c, sizeof c, &err),
           err.message);
    printf("bad_effect %d %s\n", demstep_scene_set_effects(s, 64, &err), err.message);
    printf("bad_after_failure %d %s\n",
           demstep_scene_compute(s, DEMSTEP_HERTZ_CURRENT, 0.0, 0, 0, &c, sizeof c, &err), err.message);
    demstep_scene_free(&s, &err);
  }

  {
    /* a clump of two overlapping spheres (masses 1 and 1.5), 1e-3 into a
       floor, linear law k_n = 1e4: one rigid body with a full tensor */
    double x[6] = {0.3, -0.2, 1.2, 0.9, 0.2, 1.8}, m[2] = {1.0, 1.5}, r[2] = {1.0, 1.0};
    double point[3] = {0.0, 0.0, 0.201}, normal[3] = {0.0, 0.0, 1.0}, gst, exadem;
    double mass = 2.5, com[3] = {0.0, 0.0, 0.0}, zero[9] = {0.0};
    int body_of[2] = {1, 1};
    demstep_scene *s = NULL;
    demstep_scene_result c;
    if (demstep_scene_create(3, &s, &err) != DEMSTEP_OK ||
        demstep_scene_set_particles(s, 2, x, m, r, NULL, NULL, NULL, &err) != DEMSTEP_OK ||
        demstep_scene_add_walls(s, 1, point, normal, &err) != DEMSTEP_OK ||
        demstep_scene_set_contact_law(s, DEMSTEP_LAW_LINEAR, 1.0e4, 0.0, &err) != DEMSTEP_OK ||
        demstep_scene_set_effects(s, DEMSTEP_EFFECT_CONTACTS | DEMSTEP_EFFECT_WALLS | DEMSTEP_EFFECT_ROTATION,
                                  &err) != DEMSTEP_OK ||
        demstep_scene_set_bodies(s, body_of, 0.0, 0, NULL, NULL, NULL, &err) != DEMSTEP_OK ||
        demstep_scene_compute(s, DEMSTEP_HERTZ_CURRENT, 0.0, 0, 0, &c, sizeof c, &err) != DEMSTEP_OK ||
        demstep_scene_body_peer_steps(s, &gst, &exadem, &err) != DEMSTEP_OK) {
      fprintf(stderr, "clump: %s\n", err.message);
      demstep_scene_free(&s, NULL);
      return 1;
    }
    put("clump_omega_max", c.omega_max);
    put("clump_dt_critical_eigen", c.dt_critical_eigen);
    put("clump_yade_gst", gst);
    put("clump_exadem", exadem);
    demstep_scene_free(&s, &err);
    /* a body given a singular tensor: refused by name */
    demstep_scene_create(3, &s, &err);
    demstep_scene_set_particles(s, 2, x, m, r, NULL, NULL, NULL, &err);
    printf("bad_singular %d %s %s\n", demstep_scene_set_bodies(s, body_of, 0.0, 1, &mass, com, zero, &err),
           err.where, err.message);
    demstep_scene_free(&s, &err);
  }

  {
    /* two spheres 0.1 apart held by Yade's CohFrictPhys bond (young 1e5,
       poisson 0.3, alpha_kr = alpha_ktw = 2): normal, shear, bending, twisting */
    double x[6] = {0.0, 0.0, 0.0, 1.2, 1.1, 0.9}, m[2] = {1.0, 1.5}, r[2] = {1.0, 0.9};
    double p[4] = {1.0e5, 0.3, 2.0, 2.0};
    int pair[2] = {0, 1};
    demstep_scene *s = NULL;
    demstep_scene_result c;
    if (demstep_scene_create(3, &s, &err) != DEMSTEP_OK ||
        demstep_scene_set_particles(s, 2, x, m, r, NULL, NULL, NULL, &err) != DEMSTEP_OK ||
        demstep_scene_add_bonds(s, 1, pair, &err) != DEMSTEP_OK ||
        demstep_scene_set_bond_model(s, DEMSTEP_BOND_YADE, 4, p, &err) != DEMSTEP_OK ||
        demstep_scene_compute(s, DEMSTEP_HERTZ_CURRENT, 0.0, 0, 0, &c, sizeof c, &err) != DEMSTEP_OK) {
      fprintf(stderr, "bond: %s\n", err.message);
      demstep_scene_free(&s, NULL);
      return 1;
    }
    put("bond_omega_max", c.omega_max);
    put("bond_dt_critical_eigen", c.dt_critical_eigen);
    demstep_scene_free(&s, &err);
  }

  {
    /* a solver's own arrays: three spheres in a row (1D), the middle one light;
       the top mode's shares per particle and contact */
    double x[3] = {0.0, 1.9e-3, 3.8e-3}, m[3] = {1.0e-3, 2.0e-4, 1.0e-3}, r[3] = {1.0e-3, 1.0e-3, 1.0e-3};
    double k = 1.0e4, shares[3], contact_shares[2], wall_shares[3];
    int pairs[4] = {0, 1, 1, 2};
    demstep_scene_result c;
    if (demstep_solver_participation(1, 3, x, m, r, NULL, 2, pairs, 1, &k, NULL, NULL, NULL, 0, NULL, NULL,
                                     NULL, NULL, NULL, NULL, NULL, DEMSTEP_EIGEN_AUTO, 0.0, &c, sizeof c,
                                     shares, contact_shares, wall_shares, &err) != DEMSTEP_OK) {
      fprintf(stderr, "solver: %s\n", err.message);
      return 1;
    }
    put("solver_dt_critical_eigen", c.dt_critical_eigen);
    put("solver_share_1", shares[0]);
    put("solver_share_2", shares[1]);
    put("solver_contact_share_1", contact_shares[0]);
  }

  {
    demstep_contact c;
    double n;
    demstep_contact_with_onset(20.0, 0.5, 0.1, &c, &err);
    put("contact_restitution", c.restitution);
    demstep_n_for_tolerance(DEMSTEP_QUANTITY_RESTITUTION, 1.0e-3, 0.0, 0.0, &n, &err);
    put("n_for_tolerance", n);
  }

  /* bad input: statuses and messages, never a crash */
  printf("bad_null %d %s\n", demstep_critical_time_step(&spring, NULL, &err), err.message);
  printf("bad_nan %d %s\n", demstep_harmonic_error(NAN, 0.9, 5.0, &e, &err), err.message);
  printf("bad_empty %d %s\n",
         demstep_simulated_stiffness(0.01, 1.0e5, 1.0e-3, NULL, 0, DEMSTEP_STEPS_FRACTION, 0.5,
                                     DEMSTEP_PICK_LARGEST_STEP, DEMSTEP_AGGREGATE_MEAN, NULL, NULL,
                                     NULL, NULL, &err),
         err.message);
  printf("bad_mass %d %s\n",
         demstep_spring_new(-1.0, 1.0, 0.0, 1, DEMSTEP_DASHPOT_LAGGED, &spring, &err), err.message);
  printf("bad_noerr %d\n", demstep_harmonic_error(10.0, 0.5, 20.0, &e, NULL));
  {
    demstep_contact c;
    printf("bad_onset %d %s\n", demstep_contact_with_onset(20.0, 1.5, 0.0, &c, &err), err.message);
  }
  return 0;
}
