// A C++ program using demstep through the C header: the same numbers as the C
// and Fortran programs, printed as "name value" with 17 significant digits.
#include <cstdio>
#include <vector>
#include "demstep.h"

static void put(const char *name, double value) { std::printf("%s %.16e\n", name, value); }

int main() {
  demstep_error err;
  demstep_spring spring;
  demstep_spring_state state{0.0, 1.0, 0};
  double dt_crit = 0.0, e = 0.0;
  if (demstep_spring_new(0.01, 1.0e5, 0.0, 1, DEMSTEP_DASHPOT_LAGGED, &spring, &err) != DEMSTEP_OK) {
    std::fprintf(stderr, "spring: %s\n", err.message);
    return 1;
  }
  demstep_critical_time_step(&spring, &dt_crit, &err);
  put("dt_critical", dt_crit);
  for (int i = 0; i < 1000; ++i) demstep_spring_step(&spring, 0.1 * dt_crit, &state, &err);
  put("x_1000", state.x);
  put("v_1000", state.v);
  demstep_harmonic_error(19.316, 0.9, 9.658, &e, &err);
  put("e_half_period", e);
  demstep_harmonic_error(1000.0, 1.0 - 1.0e-9, 1.0e7 + 1.0, &e, &err);
  put("e_hard", e);
  std::vector<double> lambdas(10);
  for (int i = 0; i < 10; ++i) lambdas[i] = 0.9 + (0.99 - 0.9) * i / 9.0;
  demstep_stiffness_result res{};
  if (demstep_simulated_stiffness(0.01, 1.0e5, 1.0e-3, lambdas.data(), 10, DEMSTEP_STEPS_FRACTION,
                                  0.5, DEMSTEP_PICK_LARGEST_STEP, DEMSTEP_AGGREGATE_MEAN, nullptr,
                                  nullptr, nullptr, &res, &err) != DEMSTEP_OK) {
    std::fprintf(stderr, "procedure: %s\n", err.message);
    return 1;
  }
  put("n_star", res.n_star);
  put("lambda_star", res.lambda_star);
  put("dt", res.dt);
  put("stiffness_actual", res.stiffness_actual);
  return 0;
}
