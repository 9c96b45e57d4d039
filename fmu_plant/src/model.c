/* Longitudinal equations of the vehicle plant and the step that joins them with the planar
 * motion of planar.c (see fmu_plant/README.md).
 *
 * One step of h <= PLANT_STEP_S (normally exactly PLANT_STEP_S; shorter only where a
 * communication point falls between two points of the 1 ms grid):
 *   steering    the road-wheel angle follows the command through a lag and a rate limit (planar.c)
 *   powertrain  F_lag += a_t (throttle * F_max - F_lag),  F_d = min(F_lag, P_max / max(w_d r, 1 m/s))
 *   brakes      u = min(brake(t - T_d), brake(t - f_d T_d)),  p += a (u - p) with a from tau_b
 *               while p rises and from f_tau tau_b while it falls (release: no pad travel,
 *               the valves open; f_d = f_tau = 1 by default),  per-axle ABS modulation of p
 *   tyres       kappa = (w r - u) / max(u, V_FLOOR) with u the wheel's own forward speed,
 *               Fx = mu D Fz sin(C atan(B k - E (B k - atan(B k))))
 *   wheels      J dw/dt = T_drive - T_brake - Fx r     (linearly implicit Euler, w >= 0)
 *   lateral     Fy from the slip angle (planar.c); Fx and Fy limited together to the friction ellipse
 *   chassis     m dv/dt = (tyre forces along the velocity) - F_aero - m g sin(grade) - F_roll   (v >= 0)
 *   body        sideslip, yaw rate and pose (planar.c)
 * With the wheel straight the planar terms are exact zeros and ones, so every longitudinal
 * output is the longitudinal-only plant's bit for bit (tests/fmu/test_longitudinal_golden.py).
 * Deterministic: no state outside PlantModel, no accumulated time. */
#include "model.h"

#include <math.h>
#include <stdio.h>

#include "glibc_compat.h"

#define GRAVITY_MPS2 9.80665
/* Slip denominator floor, m/s: keeps the slip finite at standstill. */
#define SLIP_SPEED_FLOOR_MPS 0.5
/* Power-limit speed floor, m/s: below it the traction force limit governs. */
#define POWER_SPEED_FLOOR_MPS 1.0
/* ABS works above this speed (real systems cut out near 1-2 m/s). */
#define ABS_MIN_SPEED_MPS 1.5
/* ABS pressure dump and re-apply rates, normalised pressure per second. */
#define ABS_DUMP_RATE_PER_S 12.0
#define ABS_APPLY_RATE_PER_S 4.0
/* ABS cycling ends when the pedal pressure falls below this. */
#define ABS_PEDAL_RELEASED 0.02

const char *plant_check_parameters(const PlantModel *m, char *buf, size_t len) {
    const PlantVariables *p = &m->var;
    if (!(p->cg_to_front_axle < p->wheelbase)) {
        snprintf(buf, len, "parameter 'cg_to_front_axle' = %g must be below 'wheelbase' = %g",
                 p->cg_to_front_axle, p->wheelbase);
        return buf;
    }
    if (!(p->abs_slip_reapply < p->abs_slip_release)) {
        snprintf(buf, len, "parameter 'abs_slip_reapply' = %g must be below 'abs_slip_release' = %g",
                 p->abs_slip_reapply, p->abs_slip_release);
        return buf;
    }
    return NULL;
}

/* Time constant of falling brake pressure, s. */
static double release_tau(const PlantVariables *p) {
    return p->brake_release_time_constant_fraction * p->brake_time_constant;
}

void plant_initialize(PlantModel *m) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    PlantDerived *k = &m->k;
    *s = (PlantState){0};
    s->v_mps = p->v0;
    s->x_m = p->x0;
    s->y_m = p->y0;
    s->yaw_rad = p->yaw0;
    s->omega_radps[PLANT_FRONT] = p->v0 / p->wheel_radius;
    s->omega_radps[PLANT_REAR] = p->v0 / p->wheel_radius;
    s->delay_len = (int)lround(p->brake_dead_time / PLANT_STEP_S);
    s->release_delay_len = (int)lround(p->brake_release_dead_time_fraction * p->brake_dead_time / PLANT_STEP_S);
    k->alpha_brake = 1.0 - exp(-PLANT_STEP_S / p->brake_time_constant);
    k->alpha_release = 1.0 - exp(-PLANT_STEP_S / release_tau(p));
    k->alpha_throttle = 1.0 - exp(-PLANT_STEP_S / p->throttle_time_constant);
    k->axle_inertia = 2.0 * p->wheel_inertia;
    k->brake_share[PLANT_FRONT] = p->brake_front_share;
    k->brake_share[PLANT_REAR] = 1.0 - p->brake_front_share;
    k->drive_share[PLANT_FRONT] = p->drive_front_share;
    k->drive_share[PLANT_REAR] = 1.0 - p->drive_front_share;
    k->alpha_steer = plant_lag_factor(PLANT_STEP_S, p->steering_time_constant);
    k->cg_to_rear_axle = p->wheelbase - p->cg_to_front_axle;
    k->longitudinal = (TyreShape){p->tyre_B, p->tyre_C, p->tyre_E};
    /* B C D = the cornering stiffness per unit load: the slope at zero slip angle */
    TyreShape lateral = {p->tyre_cornering_stiffness / (p->tyre_lateral_C * p->tyre_lateral_D),
                         p->tyre_lateral_C, p->tyre_lateral_E};
    plant_tyre_curve_build(&k->longitudinal_curve, &k->longitudinal, false);
    plant_tyre_curve_build(&k->lateral, &lateral, true);
    plant_angle_trig_set(&s->grade_trig, p->grade);
    plant_planar_initialize(m);
    plant_publish_outputs(m);
}

/* Brake command after the hydraulic dead times: a ring buffer of delay_len steps with a
 * second tap release_delay_len (<= delay_len) steps back. The pressure follows the smaller
 * of the two, so a rise arrives after T_d and a fall after T_r. */
static double delayed_brake(PlantState *s, double brake) {
    if (s->delay_len == 0) {
        return brake;
    }
    double out = s->delay_buf[s->delay_head];
    if (s->release_delay_len < s->delay_len) {
        double recent = s->release_delay_len == 0 ? brake :
            s->delay_buf[(s->delay_head - s->release_delay_len + s->delay_len) % s->delay_len];
        out = fmin(out, recent);
    }
    s->delay_buf[s->delay_head] = brake;
    s->delay_head = (s->delay_head + 1) % s->delay_len;
    return out;
}

/* Axle normal loads, N, with static grade and longitudinal load transfer. */
static void axle_loads(const PlantModel *m, double fz[PLANT_AXLES]) {
    const PlantVariables *p = &m->var;
    const AngleTrig *grade = &m->st.grade_trig;
    double weight = p->mass * GRAVITY_MPS2;
    double lr = p->wheelbase - p->cg_to_front_axle;
    double transfer = (p->mass * m->st.a_mps2 + weight * grade->s) * p->cg_height;
    fz[PLANT_FRONT] = plant_clamp((weight * grade->c * lr - transfer) / p->wheelbase, 0.0, weight);
    fz[PLANT_REAR] = plant_clamp(weight * grade->c - fz[PLANT_FRONT], 0.0, weight);
}

/* ABS, three-phase (dump / hold / re-apply) on the braking slip -kappa:
 * above abs_slip_release dump the axle pressure, below abs_slip_reapply raise it
 * again at a limited rate, in between hold it. Until the first dump the axle
 * simply follows the pedal pressure. */
static void abs_modulate(PlantModel *m, int axle, double kappa, double h) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    double *pa = &s->axle_pressure[axle];
    if (!p->abs_enabled || s->v_mps < ABS_MIN_SPEED_MPS || s->pressure < ABS_PEDAL_RELEASED) {
        s->abs_cycling[axle] = 0;
        *pa = s->pressure;
        return;
    }
    double slip = -kappa;
    if (slip > p->abs_slip_release) {
        s->abs_cycling[axle] = 1;
        *pa = fmax(0.0, *pa - ABS_DUMP_RATE_PER_S * h);
    } else if (!s->abs_cycling[axle]) {
        *pa = s->pressure;
    } else if (slip < p->abs_slip_reapply) {
        *pa = *pa + ABS_APPLY_RATE_PER_S * h;
    }
    *pa = fmin(*pa, s->pressure);
}

/* Fx at slip kappa and its slope: driving straight from the formula (the longitudinal-only
 * plant's arithmetic), else from its table (tyre_curve.c). */
static double longitudinal_force(const PlantModel *m, double kappa, double peak_n, double *slope) {
    if (m->st.straight) {
        return plant_magic_formula(&m->k.longitudinal, kappa, peak_n, slope);
    }
    double dg;
    double g = plant_tyre_curve(&m->k.longitudinal_curve, kappa, &dg);
    *slope = peak_n * dg;
    return peak_n * g;
}

/* One axle: tyre force and linearly implicit wheel update; u_mps is the contact point's
 * forward speed in the wheel's frame (the vehicle speed while the wheel is straight).
 * f holds the axle's pure lateral force; both forces are limited together to the friction
 * ellipse (planar.c). Returns Fx, N. */
static double axle_step(PlantModel *m, int axle, double fz_n, double u_mps, AxleForces *f, double h) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    double r = p->wheel_radius;
    double w = s->omega_radps[axle];
    double den = fmax(u_mps, SLIP_SPEED_FLOOR_MPS);
    double kappa = (w * r - u_mps) / den;
    double peak = p->road_friction * p->tyre_D * fz_n;
    double slope;
    double fx = longitudinal_force(m, kappa, peak, &slope);
    if (f->fy[axle] != 0.0) {  /* with the wheel straight this is skipped: Fx as before */
        double scale = plant_friction_ellipse(m, fz_n, fx, f->fy[axle]);
        fx *= scale;
        slope *= scale;
        f->fy[axle] *= scale;
        f->fy_slope[axle] *= scale;
    }
    abs_modulate(m, axle, kappa, h);
    double t_drive = m->k.drive_share[axle] * s->drive_force_n * r;
    double t_brake = m->k.brake_share[axle] * s->axle_pressure[axle] * p->max_brake_force * r;
    /* Only the stabilising part of the slope enters the implicit term. */
    double stiff = fmax(slope, 0.0) * r / den;
    double j = m->k.axle_inertia;
    double w_new = w + h * (t_drive - t_brake - r * fx) / (j + h * r * stiff);
    if (w_new < 0.0) {
        w_new = 0.0; /* the brake holds the wheel; nothing turns it backwards */
    }
    s->omega_radps[axle] = w_new;
    return plant_clamp(fx + stiff * (w_new - w), -peak, peak);
}

double plant_lag_factor(double h, double tau) {
    return tau > 0.0 ? 1.0 - exp(-h / tau) : 1.0;
}

/* First-order lag factors of one step: the ones derived at initialisation for a full step
 * (so whole steps compute exactly what they always did), else for h. */
typedef struct {
    double throttle, brake, release, steer;
} LagFactors;

static LagFactors lag_factors(const PlantModel *m, double h) {
    if (h == PLANT_STEP_S) {
        return (LagFactors){m->k.alpha_throttle, m->k.alpha_brake, m->k.alpha_release, m->k.alpha_steer};
    }
    const PlantVariables *p = &m->var;
    return (LagFactors){plant_lag_factor(h, p->throttle_time_constant), plant_lag_factor(h, p->brake_time_constant),
                        plant_lag_factor(h, release_tau(p)), plant_lag_factor(h, p->steering_time_constant)};
}

static void powertrain_and_brake_step(PlantModel *m, const LagFactors *lag, bool enters_cell) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    s->drive_force_lag_n += lag->throttle * (p->throttle * p->max_drive_force - s->drive_force_lag_n);
    double w_driven = m->k.drive_share[PLANT_FRONT] * s->omega_radps[PLANT_FRONT] +
                      m->k.drive_share[PLANT_REAR] * s->omega_radps[PLANT_REAR];
    double v_driven = fmax(w_driven * p->wheel_radius, POWER_SPEED_FLOOR_MPS);
    s->drive_force_n = fmin(s->drive_force_lag_n, p->max_power / v_driven);
    if (enters_cell) {
        s->brake_delayed = delayed_brake(s, p->brake);
    }
    double a_p = s->brake_delayed < s->pressure ? lag->release : lag->brake;
    s->pressure += a_p * (s->brake_delayed - s->pressure);
}

/* The tyre forces of one step and the wheels' update; returns the force along the velocity.
 * Driving straight, the axles' forward speeds are v and no lateral force arises: the planar
 * kinematics and body forces are left out (their terms would be exact zeros and ones). */
static double tyre_step(PlantModel *m, double h, PlanarKinematics *kin, AxleForces *f, BodyForces *body) {
    double fz[PLANT_AXLES];
    axle_loads(m, fz);
    if (m->st.straight) {
        *f = (AxleForces){{0.0}, {0.0}, {0.0}};
        f->fx[PLANT_FRONT] = axle_step(m, PLANT_FRONT, fz[PLANT_FRONT], m->st.v_mps, f, h);
        f->fx[PLANT_REAR] = axle_step(m, PLANT_REAR, fz[PLANT_REAR], m->st.v_mps, f, h);
        return f->fx[PLANT_FRONT] + f->fx[PLANT_REAR];
    }
    plant_planar_kinematics(m, kin);
    plant_lateral_forces(m, fz, kin, f);
    f->fx[PLANT_FRONT] = axle_step(m, PLANT_FRONT, fz[PLANT_FRONT], kin->u[PLANT_FRONT], f, h);
    f->fx[PLANT_REAR] = axle_step(m, PLANT_REAR, fz[PLANT_REAR], kin->u[PLANT_REAR], f, h);
    *body = plant_body_forces(m, kin, f);
    return body->along;
}

void plant_step(PlantModel *m, double h, bool enters_cell) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    LagFactors lag = lag_factors(m, h);
    plant_steering_step(m, h, lag.steer);
    powertrain_and_brake_step(m, &lag, enters_cell);
    const AngleTrig *grade = plant_angle_trig(&s->grade_trig, p->grade);
    s->straight = plant_planar_is_straight(m);
    PlanarKinematics kin;
    AxleForces f;
    BodyForces body;
    double along = tyre_step(m, h, &kin, &f, &body);
    double v = s->v_mps;
    double f_aero = 0.5 * p->air_density * p->drag_area * v * v;
    double f_grade = p->mass * GRAVITY_MPS2 * grade->s;
    double f_roll = p->rolling_resistance * p->mass * GRAVITY_MPS2 * grade->c;
    /* Rolling resistance is Coulomb-like: it stops the car but never reverses it. */
    double v_new = v + h * (along - f_aero - f_grade) / p->mass;
    v_new = v_new > 0.0 ? fmax(0.0, v_new - h * f_roll / p->mass) : 0.0;
    s->a_mps2 = (v_new - v) / h;
    if (s->straight) {
        plant_straight_step(m, h, v_new);
    } else {
        plant_planar_step(m, h, &kin, &body, &f, v_new);
    }
    s->v_mps = v_new;
}

void plant_publish_outputs(PlantModel *m) {
    PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    const AngleTrig *beta = plant_angle_turn(&s->beta_trig, s->beta_rad);
    p->x = s->x_m;
    p->v = s->v_mps;
    p->a = s->a_mps2;
    p->wheel_speed_fl = s->omega_radps[PLANT_FRONT];
    p->wheel_speed_fr = s->omega_radps[PLANT_FRONT];
    p->wheel_speed_rl = s->omega_radps[PLANT_REAR];
    p->wheel_speed_rr = s->omega_radps[PLANT_REAR];
    p->brake_pressure = s->pressure * p->max_brake_force;
    p->drive_force = s->drive_force_n;
    p->y = s->y_m;
    p->yaw = s->yaw_rad;
    p->yaw_rate = s->yaw_rate_radps;
    p->ay = s->ay_mps2;
    p->ax = s->ax_mps2;
    p->vx = s->v_mps * beta->c;
    p->vy = s->v_mps * beta->s;
    p->delta = s->delta_rad;
}
