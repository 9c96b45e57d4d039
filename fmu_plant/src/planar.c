/* Planar motion of the vehicle plant: the steering actuator, the single-track lateral and yaw
 * dynamics of the CommonRoad ST model with Magic Formula tyres in a friction ellipse, its
 * kinematic form at low speed, and the pose (fmu_plant/README.md, "Planar motion").
 *
 *   steering  d_cmd = clamp(sw / i_s + d_req, +-d_max),  d += clamp(a_s (d_cmd - d), +-dd_max h)
 *   slip      alpha = atan2(-w, |u|) per axle; (u, w) the contact-point velocity in the wheel frame
 *   tyres     Fy0 = mu D_y Fz sin(C_y atan(B_y alpha - E_y (B_y alpha - atan(B_y alpha)))),
 *             B_y C_y D_y = C_alpha / Fz;  friction ellipse: where (Fx0 / (mu D_x Fz))^2 +
 *             (Fy0 / (mu D_y Fz))^2 = q > 1, both forces shrink by 1 / sqrt(q)
 *   body      m v (beta' + r) = Fxf sin(d - beta) + Fyf cos(d - beta) - Fxr sin(beta) + Fyr cos(beta)
 *             I r' = l_f (Fxf sin(d) + Fyf cos(d)) - l_r Fyr          (linearly implicit Euler)
 *   slow      v < 0.1 m/s: beta = atan(l_r tan(d) / L),  r = v cos(beta) tan(d) / L   (kinematic)
 *   pose      psi += h (r + r') / 2,  (x, y) += h (v + v') / 2 (cos, sin)(mean psi + mean beta)
 * References: M. Althoff, M. Koschi, S. Manzinger, "CommonRoad: Composable Benchmarks for Motion
 * Planning on Roads", IEEE IV 2017, and M. Althoff, G. Wuersching, "CommonRoad: Vehicle Models"
 * (version 2020a), section 7 (ST: body equations, low-speed switch, parameters); the force terms
 * at full angles as in R. Rajamani, "Vehicle Dynamics and Control", 2nd ed. 2012, section 2.3. */
#include "model.h"

#include <math.h>

#include "glibc_compat.h"

/* Below this speed the body moves kinematically: CommonRoad ST switches at |v| < 0.1 m/s. */
#define KINEMATIC_SPEED_MPS 0.1

/* Sideslip at the centre of gravity of a car rolling without lateral slip, at the road-wheel
 * angle of delta_trig (tan = sin / cos: |delta| < pi / 2). */
static double kinematic_sideslip(const PlantModel *m) {
    const AngleTrig *d = &m->st.delta_trig;
    return atan(m->k.cg_to_rear_axle * (d->s / d->c) / m->var.wheelbase);
}

/* Yaw rate of a car rolling without lateral slip at speed v, at the sideslip and road-wheel
 * angle of beta_trig and delta_trig. */
static double kinematic_yaw_rate(const PlantModel *m, double v) {
    const AngleTrig *d = &m->st.delta_trig;
    return v * m->st.beta_trig.c * (d->s / d->c) / m->var.wheelbase;
}

/* The body rolling without lateral slip at speed v: sideslip and yaw rate from the road wheel. */
static void kinematic_motion(PlantModel *m, double v) {
    PlantState *s = &m->st;
    s->beta_rad = kinematic_sideslip(m);
    plant_angle_turn(&s->beta_trig, s->beta_rad);
    s->yaw_rate_radps = kinematic_yaw_rate(m, v);
}

/* The driver's steering-wheel angle through the steering ratio plus the ECU's overlay, limited. */
static double steering_command(const PlantVariables *p) {
    return plant_clamp(p->steering_wheel_angle / p->steering_ratio + p->steer_request,
                       -p->steering_angle_max, p->steering_angle_max);
}

void plant_planar_initialize(PlantModel *m) {
    PlantState *s = &m->st;
    s->delta_rad = steering_command(&m->var);
    plant_angle_trig_set(&s->delta_trig, s->delta_rad);
    plant_angle_trig_set(&s->beta_trig, 0.0);
    kinematic_motion(m, s->v_mps);
    plant_angle_trig_set(&s->course_trig, s->yaw_rad + s->beta_rad);
}

void plant_steering_step(PlantModel *m, double h, double a_steer) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    double command = steering_command(p);
    if (command == s->delta_rad) {
        return;  /* the wheel is where it is told to be */
    }
    double limit = p->steering_rate_max * h;
    double change = plant_clamp(a_steer * (command - s->delta_rad), -limit, limit);
    s->delta_rad = plant_clamp(s->delta_rad + change, -p->steering_angle_max, p->steering_angle_max);
    plant_angle_turn(&s->delta_trig, s->delta_rad);
}

void plant_planar_kinematics(PlantModel *m, PlanarKinematics *kin) {
    PlantState *s = &m->st;
    const AngleTrig *beta = plant_angle_turn(&s->beta_trig, s->beta_rad);
    kin->cos_beta = beta->c;
    kin->sin_beta = beta->s;
    kin->cos_delta = s->delta_trig.c;
    kin->sin_delta = s->delta_trig.s;
    double u = s->v_mps * kin->cos_beta;  /* the body's velocity at its centre of gravity */
    double w = s->v_mps * kin->sin_beta;
    double w_front = w + m->var.cg_to_front_axle * s->yaw_rate_radps;
    kin->u[PLANT_FRONT] = u * kin->cos_delta + w_front * kin->sin_delta;
    kin->w[PLANT_FRONT] = w_front * kin->cos_delta - u * kin->sin_delta;
    kin->u[PLANT_REAR] = u;
    kin->w[PLANT_REAR] = w - m->k.cg_to_rear_axle * s->yaw_rate_radps;
}

void plant_lateral_forces(const PlantModel *m, const double fz_n[PLANT_AXLES], const PlanarKinematics *kin,
                          AxleForces *f) {
    const PlantVariables *p = &m->var;
    bool kinematic = m->st.v_mps < KINEMATIC_SPEED_MPS;
    for (int axle = 0; axle < PLANT_AXLES; ++axle) {
        double peak = p->road_friction * p->tyre_lateral_D * fz_n[axle];
        f->fy[axle] = 0.0;
        f->fy_slope[axle] = 0.0;
        if (kinematic || !(peak > 0.0)) {
            continue;
        }
        if (kin->w[axle] == 0.0) {  /* rolling straight: no slip angle, no force */
            f->fy_slope[axle] = m->var.tyre_cornering_stiffness * m->var.road_friction * fz_n[axle];
            continue;
        }
        double slope;  /* the slip angle alpha = atan2(-w, |u|) through the tabulated curve */
        f->fy[axle] = plant_lateral_tyre_force(&m->k.lateral, kin->w[axle], fabs(kin->u[axle]), peak, &slope);
        f->fy_slope[axle] = fmax(slope, 0.0);
    }
}

/* The friction ellipse (J. Y. Wong, "Theory of Ground Vehicles", ch. 1, tractive effort and
 * cornering force): a tyre's resultant force lies within (Fx / Fx_max)^2 + (Fy / Fy_max)^2 <= 1.
 * Pure-slip forces outside it are scaled together onto it, keeping their direction. */
double plant_friction_ellipse(const PlantModel *m, double fz_n, double fx_n, double fy_n) {
    const PlantVariables *p = &m->var;
    double peak_x = p->road_friction * p->tyre_D * fz_n;
    double peak_y = p->road_friction * p->tyre_lateral_D * fz_n;
    if (!(peak_x > 0.0 && peak_y > 0.0)) {
        return 0.0;  /* no load or no friction: no force */
    }
    double qx = fx_n / peak_x, qy = fy_n / peak_y;
    double q = qx * qx + qy * qy;
    return q > 1.0 ? 1.0 / sqrt(q) : 1.0;
}

BodyForces plant_body_forces(const PlantModel *m, const PlanarKinematics *kin, const AxleForces *f) {
    double fxf = f->fx[PLANT_FRONT], fyf = f->fy[PLANT_FRONT];
    double fxr = f->fx[PLANT_REAR], fyr = f->fy[PLANT_REAR];
    /* cos and sin of delta - beta, the front wheel's angle to the velocity */
    double c_db = kin->cos_delta * kin->cos_beta + kin->sin_delta * kin->sin_beta;
    double s_db = kin->sin_delta * kin->cos_beta - kin->cos_delta * kin->sin_beta;
    BodyForces b;
    b.along = fxf * c_db - fyf * s_db + fxr * kin->cos_beta + fyr * kin->sin_beta;
    b.across = fxf * s_db + fyf * c_db - fxr * kin->sin_beta + fyr * kin->cos_beta;
    b.yaw_moment = m->var.cg_to_front_axle * (fxf * kin->sin_delta + fyf * kin->cos_delta) -
                   m->k.cg_to_rear_axle * fyr;
    return b;
}

/* Linearly implicit Euler step of (beta, r): (1 - h J) d = h f, with J the Jacobian of the
 * right-hand side through the slip angles (d alpha_f = -d beta - l_f dr / v, d alpha_r =
 * -d beta + l_r dr / v) and the tyre slopes. The lateral modes have eigenvalues of about
 * -C_alpha / (m v), -400 /s at 0.5 m/s: explicit Euler at 1 ms would be unstable below
 * about 0.2 m/s; this step is stable down to the kinematic switch. */
static void dynamic_step(PlantModel *m, double h, const BodyForces *b, const AxleForces *f) {
    const PlantVariables *p = &m->var;
    PlantState *s = &m->st;
    double v = s->v_mps, lf = p->cg_to_front_axle, lr = m->k.cg_to_rear_axle;
    double mv = p->mass * v, cf = f->fy_slope[PLANT_FRONT], cr = f->fy_slope[PLANT_REAR];
    double f_beta = b->across / mv - s->yaw_rate_radps;
    double f_r = b->yaw_moment / p->yaw_inertia;
    double moment_slope = cr * lr - cf * lf;
    double j11 = -(cf + cr) / mv;
    double j12 = -1.0 + moment_slope / (mv * v);
    double j21 = moment_slope / p->yaw_inertia;
    double j22 = -(cf * lf * lf + cr * lr * lr) / (p->yaw_inertia * v);
    double a11 = 1.0 - h * j11, a12 = -h * j12, a21 = -h * j21, a22 = 1.0 - h * j22;
    double det = a11 * a22 - a12 * a21;  /* >= 1 - O(h^2): Cauchy-Schwarz on the slopes */
    s->beta_rad += h * (a22 * f_beta - a12 * f_r) / det;
    s->yaw_rate_radps += h * (a11 * f_r - a21 * f_beta) / det;
}

void plant_planar_step(PlantModel *m, double h, const PlanarKinematics *kin, const BodyForces *b,
                       const AxleForces *f, double v_new) {
    PlantState *s = &m->st;
    double v = s->v_mps, beta = s->beta_rad, yaw = s->yaw_rad, r = s->yaw_rate_radps;
    if (v < KINEMATIC_SPEED_MPS) {
        kinematic_motion(m, v_new);
    } else {
        dynamic_step(m, h, b, f);
    }
    s->yaw_rad += 0.5 * h * (r + s->yaw_rate_radps);
    double course = 0.5 * ((yaw + s->yaw_rad) + (beta + s->beta_rad));
    double ds = 0.5 * (v + v_new) * h;
    const AngleTrig *dir = plant_angle_turn(&s->course_trig, course);
    s->x_m += ds * dir->c;
    s->y_m += ds * dir->s;
    /* across the velocity v (beta' + r); with a along it turned into the vehicle frame by the
     * sideslip of the step's start: ay across the car, ax along it */
    double a_across = 0.5 * (v + v_new) * ((s->beta_rad - beta) + (s->yaw_rad - yaw)) / h;
    s->ay_mps2 = s->a_mps2 * kin->sin_beta + a_across * kin->cos_beta;
    s->ax_mps2 = s->a_mps2 * kin->cos_beta - a_across * kin->sin_beta;
}

bool plant_planar_is_straight(const PlantModel *m) {
    const PlantState *s = &m->st;
    return s->delta_rad == 0.0 && s->beta_rad == 0.0 && s->yaw_rate_radps == 0.0;
}

void plant_straight_step(PlantModel *m, double h, double v_new) {
    PlantState *s = &m->st;
    double ds = 0.5 * (s->v_mps + v_new) * h;
    const AngleTrig *dir = plant_angle_trig(&s->course_trig, s->yaw_rad);
    s->x_m += ds * dir->c;
    s->y_m += ds * dir->s;
    s->ay_mps2 = 0.0;
    s->ax_mps2 = s->a_mps2;
}
