/* tests/fmu/test_numeric_kernels.py: the tabulated tyre curve (fmu_plant/src/tyre_curve.c) against
 * the Magic Formula it tabulates. Arguments: B C E slip_angle(0|1). Prints the largest
 * differences of G (in units of the peak) and of dG/dq (relative to the largest |dG/dq|) over a
 * sweep of q across the table and beyond it, and the table's end N d. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "model.h"

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: %s B C E slip_angle\n", argv[0]);
        return 2;
    }
    TyreShape shape = {atof(argv[1]), atof(argv[2]), atof(argv[3])};
    int slip_angle = atoi(argv[4]);
    static TyreCurve curve;
    plant_tyre_curve_build(&curve, &shape, slip_angle);
    const int n = 100000;
    double err_g = 0.0, err_slope = 0.0, slope_max = 0.0;
    for (int k = -n; k <= n; ++k) {
        double q = 1.5 * curve.input_max * k / n + 1e-7 * curve.step * (k % 7);
        double x = slip_angle ? atan(q) : q, slope;
        double g = plant_magic_formula(&shape, x, 1.0, &slope);
        double dg_dq = slip_angle ? slope / (1.0 + q * q) : slope;
        double dg_tab;
        double g_tab = plant_tyre_curve(&curve, q, &dg_tab);
        err_g = fmax(err_g, fabs(g_tab - g));
        err_slope = fmax(err_slope, fabs(dg_tab - dg_dq));
        slope_max = fmax(slope_max, fabs(dg_dq));
    }
    printf("%.6e %.6e %.6e\n", err_g, err_slope / slope_max, curve.input_max);
    return 0;
}
