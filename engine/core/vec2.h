/* vec2.h - the 2D point operations the layout code shares (texel-space triangles), inline so
 * each caller keeps its speed.
 * Does not: know meshes or layouts (mesh.h sums a layout's areas), or hold points as floats. */
#ifndef TEXOPT_VEC2_H
#define TEXOPT_VEC2_H

/* Signed area of the triangle a, b, c (2 coordinates each): positive when counter-clockwise
 * in a frame with y up. */
static inline double texopt_signed_area(const double *a, const double *b, const double *c)
{
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

#endif
