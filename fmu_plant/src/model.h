/* The planar vehicle plant: state, derived constants and one fixed step.
 * The equations are in model.c (longitudinal) and planar.c (steering, lateral and yaw
 * motion, pose) and written out in fmu_plant/README.md. */
#ifndef PLANT_MODEL_H
#define PLANT_MODEL_H

#include <stdbool.h>
#include <math.h>
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

/* cos and sin of an angle, kept with the angle they belong to: recomputed only when it changes
 * (planar.c, plant_angle_trig). */
typedef struct {
    double angle, c, s;
} AngleTrig;

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
    /* planar motion (planar.c) */
    double delta_rad;                  /* road-wheel angle after the steering actuator */
    double beta_rad;                   /* sideslip angle at the centre of gravity */
    double yaw_rate_radps;
    double yaw_rad;
    double y_m;
    double ay_mps2;                    /* vehicle-frame lateral acceleration, last step */
    double ax_mps2;                    /* vehicle-frame longitudinal acceleration, last step */
    AngleTrig delta_trig;              /* of delta_rad: the wheel is often held */
    AngleTrig course_trig;             /* of the last course angle: constant while driving straight */
    AngleTrig grade_trig;              /* of the road grade, an input that seldom changes */
    AngleTrig beta_trig;               /* of beta_rad: the outputs and the next step's kinematics */
    bool straight;                     /* this step drives straight (plant_planar_is_straight) */
} PlantState;

/* Magic Formula coefficients of one direction (Pacejka 2012, eq. 4.49). */
typedef struct {
    double B, C, E;
} TyreShape;

/* A tyre characteristic tabulated over its input q in [0, Q] (tyre_curve.c): the Magic Formula
 * G(x) = sin(C atan(B x - E (B x - atan(B x)))) at x = q (slip ratio) or x = atan(q) (q the
 * lateral slip tan(alpha)), and dG/dq times the node spacing, at N + 1 nodes spaced at most
 * Q / N and 1 / (50 B max(1, C) max(1, |1 - E|)). */
#define TYRE_CURVE_NODES 1024
#define TYRE_CURVE_INPUT_MAX 1.0
#define TYRE_CURVE_NODES_PER_BEND 50.0
typedef struct {
    TyreShape shape;
    bool slip_angle;        /* q = tan(alpha) */
    double step, inv_step;  /* node spacing d and 1 / d */
    double input_max;       /* N d: the formula beyond */
    double g[TYRE_CURVE_NODES + 1];
    double dg[TYRE_CURVE_NODES + 1];
} TyreCurve;

/* Constants derived from the parameters once, at initialisation. */
typedef struct {
    double alpha_brake;     /* 1 - exp(-h / brake_time_constant) */
    double alpha_release;   /* 1 - exp(-h / brake_release_time_constant) */
    double alpha_throttle;  /* 1 - exp(-h / throttle_time_constant) */
    double axle_inertia;    /* kg m^2, two wheels */
    double brake_share[PLANT_AXLES];
    double drive_share[PLANT_AXLES];
    double alpha_steer;     /* 1 - exp(-h / steering_time_constant), 1 without a lag */
    double cg_to_rear_axle; /* wheelbase - cg_to_front_axle */
    TyreShape longitudinal; /* tyre_B, tyre_C, tyre_E */
    TyreCurve longitudinal_curve;  /* its table, for steps that are not straight */
    TyreCurve lateral;      /* B from the cornering stiffness, tyre_lateral_C and _D; tyre_lateral_E */
} PlantDerived;

/* The planar kinematics of one step: cos and sin of the sideslip and road-wheel angles, and
 * the velocity of each axle's contact point in its wheel's frame, m/s: u along the wheel
 * (its forward speed), w across it (to the left). */
typedef struct {
    double cos_beta, sin_beta, cos_delta, sin_delta;
    double u[PLANT_AXLES];
    double w[PLANT_AXLES];
} PlanarKinematics;

/* Tyre forces of each axle in its wheel's frame, N, and the lateral slope dFy/dalpha
 * (N/rad, never negative) for the linearly implicit lateral step. */
typedef struct {
    double fx[PLANT_AXLES];
    double fy[PLANT_AXLES];
    double fy_slope[PLANT_AXLES];
} AxleForces;

/* The tyre forces as the body feels them: along and across the velocity of the centre of
 * gravity (N) and the yaw moment about it (N m). */
typedef struct {
    double along;
    double across;
    double yaw_moment;
} BodyForces;

typedef struct {
    PlantVariables var;
    PlantState st;
    PlantDerived k;
} PlantModel;

static inline double plant_clamp(double x, double lo, double hi) {
    return x < lo ? lo : (x > hi ? hi : x);
}

/* cos and sin of an angle; of 0 without a call (the values the call would give): while the car
 * drives straight on the level its sideslip, road-wheel and grade angles are exactly 0. */
static inline void plant_cos_sin(double angle, double *c, double *s) {
    if (angle == 0.0) {
        *c = 1.0;
        *s = angle;
        return;
    }
    *c = cos(angle);
    *s = sin(angle);
}

static inline void plant_angle_trig_set(AngleTrig *t, double angle) {
    t->angle = angle;
    plant_cos_sin(angle, &t->c, &t->s);
}

/* The cached cos and sin of angle: the values of plant_cos_sin(angle), recomputed only when the
 * angle differs from the last one (the road-wheel angle while the wheel is held, the grade, the
 * heading while driving straight). */
static inline const AngleTrig *plant_angle_trig(AngleTrig *t, double angle) {
    if (angle != t->angle) {
        plant_angle_trig_set(t, angle);
    }
    return t;
}

/* Largest turn, rad, that plant_angle_turn takes by its series (beyond it: cos and sin). */
#define PLANT_SMALL_TURN_RAD 0.03125

/* The kept cos and sin of angle, for an angle that moves in small steps (the road-wheel angle,
 * the sideslip, the course while turning): the kept pair turned by d = angle - t->angle,
 *   (c, s) <- (c cos d - s sin d, s cos d + c sin d),
 * with cos d and sin d from their Taylor series to d^8 and d^7, whose remainders (d^10/10!,
 * d^9/9!) lie below 1e-19 for |d| <= 1/32 (M. Abramowitz, I. Stegun, "Handbook of Mathematical
 * Functions", 4.3.65-66); a larger change takes cos and sin of the angle itself. Each turn
 * rounds once, so the pair stays within about sqrt(steps) ulp of cos and sin of the angle (and
 * of unit length): no trig call while the car turns. */
static inline const AngleTrig *plant_angle_turn(AngleTrig *t, double angle) {
    double d = angle - t->angle;
    if (d == 0.0) {
        return t;
    }
    if (!(fabs(d) <= PLANT_SMALL_TURN_RAD)) {
        plant_angle_trig_set(t, angle);
        return t;
    }
    double d2 = d * d;
    double sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0))));
    double cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))));
    double c = t->c, s = t->s;
    t->c = c * cd - s * sd;
    t->s = s * cd + c * sd;
    t->angle = angle;
    return t;
}

/* First-order lag factor 1 - exp(-h/tau) (exact discretisation); 1 for tau = 0 (no lag). */
double plant_lag_factor(double h, double tau);

/* Magic Formula (Pacejka 2012, eq. 4.49) F = peak sin(C atan(B x - E (B x - atan(B x))))
 * and its slope dF/dx. */
static inline double plant_magic_formula(const TyreShape *t, double x, double peak_n, double *slope) {
    double bk = t->B * x;
    double phi = bk - t->E * (bk - atan(bk));
    double dphi = t->B * (1.0 - t->E + t->E / (1.0 + bk * bk));
    double theta = t->C * atan(phi);
    *slope = peak_n * cos(theta) * t->C / (1.0 + phi * phi) * dphi;
    return peak_n * sin(theta);
}


/* tyre_curve.c: the table of the characteristic of shape; slip_angle: its input is tan(alpha). */
void plant_tyre_curve_build(TyreCurve *curve, const TyreShape *shape, bool slip_angle);
/* tyre_curve.c: G(q) from the table (the formula beyond it), and dG/dq. */
double plant_tyre_curve(const TyreCurve *curve, double q, double *dg_dq);
/* tyre_curve.c: the pure lateral force, N, of an axle whose contact point moves at w across
 * and |u| = u_abs along its wheel, at peak force peak_n; slope = dFy/dalpha, N/rad. */
double plant_lateral_tyre_force(const TyreCurve *curve, double w, double u_abs, double peak_n, double *slope);

/* planar.c: the road wheel at its initial command, sideslip and yaw rate on its kinematic circle. */
void plant_planar_initialize(PlantModel *m);
/* planar.c: the steering actuator over h with lag factor a_steer. */
void plant_steering_step(PlantModel *m, double h, double a_steer);
/* planar.c: the kinematics of the current v, beta, yaw rate and delta. */
void plant_planar_kinematics(PlantModel *m, PlanarKinematics *kin);
/* planar.c: the pure-slip lateral tyre forces and their slopes (the wheel step then limits
 * them with the longitudinal forces to the friction ellipse). */
void plant_lateral_forces(const PlantModel *m, const double fz_n[PLANT_AXLES], const PlanarKinematics *kin,
                          AxleForces *f);
/* planar.c: the factor (<= 1) that puts an axle's pure-slip forces on its friction ellipse. */
double plant_friction_ellipse(const PlantModel *m, double fz_n, double fx_n, double fy_n);
/* planar.c: the axle forces resolved along and across the velocity, and the yaw moment. */
BodyForces plant_body_forces(const PlantModel *m, const PlanarKinematics *kin, const AxleForces *f);
/* planar.c: sideslip, yaw rate, heading, position and lateral acceleration over h, given the
 * speed before (v) and after (v_new) the longitudinal update. */
void plant_planar_step(PlantModel *m, double h, const PlanarKinematics *kin, const BodyForces *b,
                       const AxleForces *f, double v_new);

/* planar.c: the car drives straight: road wheel, sideslip and yaw rate exactly 0. Then every
 * lateral force, the yaw moment and the lateral acceleration are 0 and the step leaves them out. */
bool plant_planar_is_straight(const PlantModel *m);
/* planar.c: the pose over h of a car driving straight (heading unchanged), given the speed before
 * (v) and after (v_new) the longitudinal update. */
void plant_straight_step(PlantModel *m, double h, double v_new);

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
