/* The longitudinal vehicle plant: state, derived constants and one fixed step.
 * The equations are in model.c and written out in fmu_plant/README.md. */
#ifndef PLANT_MODEL_H
#define PLANT_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include "variables.h"

/* Only the FMI functions are exported; the plant's own symbols stay inside the library,
 * whoever builds it (our cmake build also sets hidden visibility; fmpy's does not). */
#if defined(__GNUC__)
#pragma GCC visibility push(hidden)
#endif

/* Fixed internal step, s: the grid t0 + n * h. doStep takes whole steps on this grid and,
 * where a communication point falls between two grid points, a shorter sub-step to it. */
#define PLANT_STEP_S 1e-3
/* Dead-time ring buffer capacity in steps (brake_dead_time max 0.5 s). */
#define PLANT_DELAY_CAP 512

enum { PLANT_FRONT = 0, PLANT_REAR = 1, PLANT_AXLES = 2 };

typedef struct {
    double omega_radps[PLANT_AXLES];   /* wheel speed, both wheels of an axle */
    double v_mps;
    double x_m;
    double a_mps2;                     /* over the last step */
    double drive_force_lag_n;          /* throttle command after the first-order lag */
    double drive_force_n;              /* after the power limit */
    double pressure;                   /* normalised, after dead time and lag */
    double axle_pressure[PLANT_AXLES]; /* normalised, after ABS modulation */
    int abs_cycling[PLANT_AXLES];      /* ABS has intervened since the pedal was applied */
    double brake_delayed;              /* brake(t - T_d) for the current 1 ms cell */
    double delay_buf[PLANT_DELAY_CAP];
    int delay_len;
    int release_delay_len;             /* steps of the shorter release dead time */
    int delay_head;
} PlantState;

/* Constants derived from the parameters once, at initialisation. */
typedef struct {
    double alpha_brake;     /* 1 - exp(-h / brake_time_constant) */
    double alpha_release;   /* 1 - exp(-h / brake_release_time_constant) */
    double alpha_throttle;  /* 1 - exp(-h / throttle_time_constant) */
    double axle_inertia;    /* kg m^2, two wheels */
    double brake_share[PLANT_AXLES];
    double drive_share[PLANT_AXLES];
} PlantDerived;

typedef struct {
    PlantVariables var;
    PlantState st;
    PlantDerived k;
} PlantModel;

/* Check relations between parameters that single ranges cannot express.
 * Returns NULL if fine, else writes a message naming the parameters into buf. */
const char *plant_check_parameters(const PlantModel *m, char *buf, size_t len);

/* Set the state from v0 and x0 and derive the constants; parameters are valid. */
void plant_initialize(PlantModel *m);

/* Advance by h (0 < h <= PLANT_STEP_S) with the current inputs. enters_cell is true for
 * the first (sub-)step of a 1 ms grid cell: only then does the brake dead-time line take
 * in the brake command and give out the one from T_d ago, so the line runs on the grid. */
void plant_step(PlantModel *m, double h, bool enters_cell);

/* Copy the state into the output variables. */
void plant_publish_outputs(PlantModel *m);

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif
