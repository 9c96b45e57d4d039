/* tests/fmu/test_numeric_kernels.py: plant_angle_turn (fmu_plant/src/model.h) against cos and sin.
 * Arguments: steps, largest step (rad), seed. Turns a kept pair by that many random steps (a
 * random walk of the angle, as a turning car's course or sideslip) and prints the largest
 * differences of the pair from cos and sin of the angle, and of its length from 1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "model.h"

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s steps max_step_rad seed\n", argv[0]);
        return 2;
    }
    long steps = atol(argv[1]);
    double max_step = atof(argv[2]);
    srand((unsigned)atoi(argv[3]));
    AngleTrig t;
    double angle = 0.3;
    plant_angle_trig_set(&t, angle);
    double err = 0.0, err_norm = 0.0;
    for (long k = 0; k < steps; ++k) {
        angle += max_step * (2.0 * rand() / RAND_MAX - 1.0);
        plant_angle_turn(&t, angle);
        err = fmax(err, fmax(fabs(t.c - cos(angle)), fabs(t.s - sin(angle))));
        err_norm = fmax(err_norm, fabs(hypot(t.c, t.s) - 1.0));
    }
    printf("%.6e %.6e\n", err, err_norm);
    return 0;
}
