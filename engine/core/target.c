/* target.c - the stretch part of a target from a symmetric 2x2 metric; see target.h. */
#include "target.h"

#include <math.h>

#define PI 3.14159265358979323846

void texopt_sym2_eigen(const double m[3], double *mu1, double *mu2, double *theta)
{
    double mean = 0.5 * (m[0] + m[2]), half = 0.5 * (m[0] - m[2]);
    double d = sqrt(half * half + m[1] * m[1]);
    *mu1 = fmax(0, mean + d);
    *mu2 = fmax(0, mean - d);
    double t = 0.5 * atan2(2 * m[1], m[0] - m[2]);
    if (t < 0)
        t += PI;
    *theta = t;
}

void texopt_target_set_stretch(texopt_triangle_target *g, double theta, double along, double across)
{
    /* V(beta) wants beta in [0, pi/2): a direction past pi/2 is the second axis. */
    if (theta < PI / 2) {
        g->beta = theta;
        g->lambda1 = along;
        g->lambda2 = across;
    } else {
        g->beta = theta - PI / 2;
        g->lambda1 = across;
        g->lambda2 = along;
    }
}

size_t texopt_targets_raise_to_floor(texopt_triangle_target *targets, const texopt_triangle_target *floor_targets,
                                     size_t count, double k)
{
    size_t raised = 0;
    for (size_t t = 0; t < count; t++) {
        const texopt_triangle_target *f = &floor_targets[t];
        if (targets[t].lambda1 * targets[t].lambda2 < k * k * f->lambda1 * f->lambda2) {
            targets[t].lambda1 = k * f->lambda1;
            targets[t].lambda2 = k * f->lambda2;
            targets[t].beta = f->beta;
            raised++;
        }
    }
    return raised;
}
