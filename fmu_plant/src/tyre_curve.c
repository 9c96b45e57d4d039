/* The tyre characteristics as tables, built once at initialisation.
 *
 * The Magic Formula (Pacejka 2012, eq. 4.49) of a slip x,
 *   G(x) = sin(C atan(B x - E (B x - atan(B x)))),   F = mu D Fz G,
 * depends on the slip and on the fixed shape (B, C, E) only: the load and the road friction
 * scale it. Evaluating it costs three transcendental calls, and the lateral slip angle
 * alpha = atan2(-w, |u|) a fourth, per axle and step: with four tyre curves per step this is
 * what made the planar plant dearer than the longitudinal one. A table holds G and dG/dq at
 * the nodes q_i = i d, i = 0..N, of its input q, and a step evaluates the cubic Hermite
 * interpolant between them (C. de Boor, "A Practical Guide to Splines", rev. ed. 2001, ch. IV):
 *   G(q) = h00(t) G_i + h10(t) d G'_i + h01(t) G_i+1 + h11(t) d G'_i+1,   t = (q - q_i) / d,
 * exact at the nodes and within d^4 max|G''''| / 384 between them. The curve bends over slips
 * of about 1 / k, k = B max(1, C) max(1, |1 - E|) (bend below), so the spacing is
 * d = min(Q / N, 1 / (TYRE_CURVE_NODES_PER_BEND k)): the error stays below 1e-8 of the peak
 * force, and that of the slope below 1e-5 of its largest value, over the parameters' ranges
 * (tests/fmu/test_numeric_kernels.py measures it against the formula; 2e-9 with the defaults). G is odd in q, so the table
 * covers 0 <= q < N d; beyond it the formula itself is evaluated.
 *   longitudinal  q = kappa, the slip ratio, Q = 1 (every braking slip; wheelspin beyond it)
 *   lateral       q = tan(alpha) = -w / |u|, Q = 1 (slip angles up to 45 degrees): no atan2
 * The longitudinal table serves only steps that are not straight: driving straight, the plant
 * evaluates the formula, as the longitudinal-only plant did, bit for bit. */
#include "model.h"

#include <math.h>

#include "glibc_compat.h"

/* G and dG/dq at q from the formula; for a slip-angle table q = tan(alpha), so the formula
 * takes alpha = atan(q) and dG/dq = dG/dalpha / (1 + q^2). */
static double formula_point(const TyreCurve *curve, double q, double *dg_dq) {
    double slope;
    if (!curve->slip_angle) {
        return plant_magic_formula(&curve->shape, q, 1.0, dg_dq);
    }
    double g = plant_magic_formula(&curve->shape, atan(q), 1.0, &slope);
    *dg_dq = slope / (1.0 + q * q);
    return g;
}

/* The inverse of the slip over which the curve bends: its argument B x (1 - E) + E atan(B x)
 * turns by B max(1, |1 - E|) per unit slip, and C multiplies the angle of the sine. */
static double bend(const TyreShape *shape) {
    return fabs(shape->B) * fmax(1.0, shape->C) * fmax(1.0, fabs(1.0 - shape->E));
}

void plant_tyre_curve_build(TyreCurve *curve, const TyreShape *shape, bool slip_angle) {
    curve->shape = *shape;
    curve->slip_angle = slip_angle;
    curve->step = fmin(TYRE_CURVE_INPUT_MAX / TYRE_CURVE_NODES, 1.0 / (TYRE_CURVE_NODES_PER_BEND * bend(shape)));
    curve->inv_step = 1.0 / curve->step;
    curve->input_max = TYRE_CURVE_NODES * curve->step;
    for (int i = 0; i <= TYRE_CURVE_NODES; ++i) {
        double dg_dq;
        curve->g[i] = formula_point(curve, i * curve->step, &dg_dq);
        curve->dg[i] = dg_dq * curve->step;  /* scaled to the node spacing */
    }
}

double plant_tyre_curve(const TyreCurve *curve, double q, double *dg_dq) {
    double q_abs = fabs(q);
    if (!(q_abs < curve->input_max)) {
        return formula_point(curve, q, dg_dq);
    }
    double x = q_abs * curve->inv_step;
    int i = (int)x;
    if (i >= TYRE_CURVE_NODES) {
        i = TYRE_CURVE_NODES - 1;
    }
    double t = x - i;
    double g0 = curve->g[i], g1 = curve->g[i + 1], d0 = curve->dg[i], d1 = curve->dg[i + 1];
    double t2 = t * t, t3 = t2 * t;
    double g = (2.0 * t3 - 3.0 * t2 + 1.0) * g0 + (t3 - 2.0 * t2 + t) * d0 + (3.0 * t2 - 2.0 * t3) * g1 +
               (t3 - t2) * d1;
    double dg_dt = 6.0 * (t2 - t) * (g0 - g1) + (3.0 * t2 - 4.0 * t + 1.0) * d0 + (3.0 * t2 - 2.0 * t) * d1;
    *dg_dq = dg_dt * curve->inv_step;  /* even in q */
    return q < 0.0 ? -g : g;
}

double plant_lateral_tyre_force(const TyreCurve *curve, double w, double u_abs, double peak_n, double *slope) {
    if (!(fabs(w) < curve->input_max * u_abs)) {  /* beyond the table (or u = 0): the formula */
        return plant_magic_formula(&curve->shape, atan2(-w, u_abs), peak_n, slope);
    }
    double s = -w / u_abs, dg_ds;
    double g = plant_tyre_curve(curve, s, &dg_ds);
    *slope = peak_n * dg_ds * (1.0 + s * s);  /* dF/dalpha = peak dG/ds ds/dalpha */
    return peak_n * g;
}
