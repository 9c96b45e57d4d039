/* The lateral tyre characteristic as a table, built once at initialisation.
 *
 * The lateral Magic Formula (Pacejka 2012, eq. 4.49) of the slip angle alpha,
 *   G(alpha) = sin(C atan(B alpha - E (B alpha - atan(B alpha)))),   Fy0 = mu D_y Fz G,
 * depends on alpha and on the fixed shape (B, C, E) only: the load and the road friction
 * scale it. Evaluating it costs the slip angle atan2 and three further transcendental
 * calls per axle and step, which is what made the planar plant dearer than the
 * longitudinal one. The table holds G and dG/ds at the nodes s_i = i * S / N of the
 * lateral slip s = tan(alpha) = -w / |u| (no atan2 needed), and the step evaluates the
 * cubic Hermite interpolant between them (Hermite interpolation: e.g. C. de Boor,
 * "A Practical Guide to Splines", rev. ed. 2001, ch. IV):
 *   G(s) = h00(t) G_i + h10(t) d G'_i + h01(t) G_i+1 + h11(t) d G'_i+1,   t = (s - s_i) / d
 * with error at most d^4 max|G''''| / 384 between the nodes (exact at them). With
 * N = TYRE_CURVE_NODES and S = TYRE_CURVE_SLIP_MAX this is below 1e-9 of the peak force for
 * the parameter ranges (tests/fmu/test_tyre_curve.py measures it against the formula).
 * Beyond S (slip angles above 45 degrees) the formula itself is evaluated. */
#include "model.h"

#include <math.h>

#include "glibc_compat.h"

/* G and dG/ds at s, from the Magic Formula in alpha = atan(s): dG/ds = dG/dalpha / (1 + s^2). */
static double curve_point(const TyreShape *shape, double s, double *dg_ds) {
    double slope;
    double g = plant_magic_formula(shape, atan(s), 1.0, &slope);
    *dg_ds = slope / (1.0 + s * s);
    return g;
}

void plant_tyre_curve_build(TyreCurve *curve, const TyreShape *shape) {
    curve->shape = *shape;
    curve->step = TYRE_CURVE_SLIP_MAX / TYRE_CURVE_NODES;
    curve->inv_step = TYRE_CURVE_NODES / TYRE_CURVE_SLIP_MAX;
    for (int i = 0; i <= TYRE_CURVE_NODES; ++i) {
        double dg_ds;
        curve->g[i] = curve_point(shape, i * curve->step, &dg_ds);
        curve->dg[i] = dg_ds * curve->step;  /* scaled to the node spacing */
    }
}

double plant_tyre_curve_force(const TyreCurve *curve, double w, double u_abs, double peak_n, double *slope) {
    double w_abs = fabs(w);
    if (!(w_abs <= TYRE_CURVE_SLIP_MAX * u_abs)) {  /* beyond the table (or u = 0): the formula */
        return plant_magic_formula(&curve->shape, atan2(-w, u_abs), peak_n, slope);
    }
    double s = w_abs / u_abs;
    double x = s * curve->inv_step;
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
    /* dF/dalpha = peak dG/ds (1 + s^2); the curve is odd in s, its slope even; s = -w / |u| */
    *slope = peak_n * dg_dt * curve->inv_step * (1.0 + s * s);
    return w > 0.0 ? -peak_n * g : peak_n * g;
}
