/* vec3.h - the few 3-vector operations the geometry code shares (camera frames, the
 * evaluation's views, lit shading's tangent frames), inline so each caller keeps its speed.
 * Does not: hold points as floats (callers convert), or do matrices beyond a triangle's
 * in-plane frame. */
#ifndef TEXOPT_VEC3_H
#define TEXOPT_VEC3_H

#include <math.h>

static inline double texopt_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void texopt_cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double texopt_distance3(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(texopt_dot3(d, d));
}

/* Scales v to unit length and returns 1; 0, v unchanged, when its length is 0 or not finite. */
static inline int texopt_normalize3(double v[3])
{
    double n = sqrt(texopt_dot3(v, v));
    if (!(n > 0.0) || !isfinite(n))
        return 0;
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
    return 1;
}

/* The columns of P are the edges b - a and c - a in an orthonormal frame of the triangle's
 * plane with x along b - a: upper triangular with a positive diagonal, so the frame turns
 * with the triangle's orientation. Returns -1 (P not meaningful) when the triangle has no
 * area, else 0. */
static inline int texopt_plane_edges(const double a[3], const double b[3], const double c[3], double P[2][2])
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n[3];
    double l1 = sqrt(texopt_dot3(e1, e1));
    texopt_cross3(e1, e2, n);
    P[0][0] = l1;
    P[1][0] = 0.0;
    P[0][1] = texopt_dot3(e1, e2) / l1;
    P[1][1] = sqrt(texopt_dot3(n, n)) / l1;
    return P[1][1] > 0 ? 0 : -1;
}

#endif
