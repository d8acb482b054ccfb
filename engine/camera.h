/* camera.h - the per-triangle orthographic camera of the triangle-wise stage.
 *
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen",
 * appendix A: the camera looks along the face normal N (from the side N points to), sits at
 * the triangle's centroid C, its right vector is R = (a - C)/|a - C| for the first corner a,
 * its up vector U = N x R. The window is the bounding box of the triangle's one-ring in
 * (R, U), padded on its short side to a square so that pixels are square, and it is mapped
 * onto a size x size viewport. Row 0 of the viewport is the top (largest U).
 *
 * This header only builds the frame and projects points; rasterising lives in uvraster.h. */
#ifndef TEXOPT_CAMERA_H
#define TEXOPT_CAMERA_H

#include <stddef.h>

#include "status.h"

typedef struct texopt_camera {
    double center[3];   /* the triangle's centroid C */
    double right[3];    /* R, unit */
    double up[3];       /* U = N x R, unit */
    double normal[3];   /* N, unit; the camera sits on the +N side looking along -N */
    double window_x0;   /* window's left edge, in R units relative to C */
    double window_y0;   /* window's bottom edge, in U units relative to C */
    double window_side; /* side of the square window, world units, > 0 */
    int size;           /* viewport side in pixels */
} texopt_camera;

/* Builds the camera of the triangle (a, b, c) whose one-ring spans ring_points (3 doubles
 * each, point_count of them; the triangle's own corners may or may not be among them, they
 * are always included). Fails with TEXOPT_E_INVALID_ARGUMENT on a degenerate triangle (no
 * normal or a corner at the centroid) or size < 2. */
texopt_status texopt_camera_create(texopt_camera *camera, const double a[3], const double b[3],
                                   const double c[3], const double *ring_points,
                                   size_t point_count, int size, char *err, size_t err_len);

/* Projects a world point to continuous viewport coordinates: screen[0] grows to the right in
 * pixels (pixel i covers [i, i + 1)), screen[1] grows downwards (row j covers [j, j + 1)),
 * *depth is the signed distance along N (larger = closer to the camera). */
void texopt_camera_project(const texopt_camera *camera, const double point[3], double screen[2],
                           double *depth);

#endif
