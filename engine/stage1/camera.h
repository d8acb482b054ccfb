/* camera.h - the per-triangle orthographic camera of the triangle-wise stage.
 *
 * Sun et al. 2022, "Efficient Texture Parameterization Driven by Perceptual-Loss-on-Screen",
 * appendix A: the camera looks along the face normal N (from the side N points to), sits at
 * the triangle's centroid C, its right vector is R = (a - C)/|a - C| for the first corner a,
 * its up vector U = N x R. The window is the bounding box in (R, U) of the triangle's corners
 * and the points given (stage 1 gives its one-ring; appendix A frames the corners alone, the
 * window of --method paper), padded on its short side to a square so that pixels are square,
 * and it is mapped onto a size x size viewport. Row 0 of the viewport is the top (largest U).
 *
 * The one-ring's window makes the zoom depend on the ring's size: a ring spanning 180 texels
 * is seen at 2.8 input texels per pixel, so a shrink to half is invisible there while the
 * evaluation (evaluate.h) shows about one texel per pixel. texopt_camera_limit_zoom narrows
 * such a window, at the same pixel count, to a given number of texels per pixel.
 *
 * This header only builds the frame and projects points; rasterising lives in uvraster.h. */
#ifndef TEXOPT_CAMERA_H
#define TEXOPT_CAMERA_H

#include <stddef.h>

#include "status.h"

/* Stage 1's default for texopt_camera_limit_zoom (BENCHMARKS.md@9f788a8 "Quality"). */
#define TEXOPT_CAMERA_MAX_ZOOM 1.25

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
texopt_status texopt_camera_create(texopt_camera *camera, const double a[3], const double b[3], const double c[3],
                                   const double *ring_points, size_t point_count, int size, char *err, size_t err_len);

/* The input texels per pixel the camera shows where the surface has texels_per_unit texels
 * per world unit (square root of texel area over 3D area). */
double texopt_camera_zoom(const texopt_camera *camera, double texels_per_unit);

/* Narrows the window of a camera from texopt_camera_create on the triangle (a, b, c) so that
 * it shows at most max_zoom input texels per pixel at texels_per_unit, keeping the viewport
 * size: centred on the centroid, moved only as far as needed to keep the whole triangle and
 * to stay inside the paper's window, and never narrower than the triangle, which is
 * always seen whole. A window already at or under max_zoom, max_zoom <= 0 or a
 * texels_per_unit that is not positive and finite leave the camera as it is. */
void texopt_camera_limit_zoom(texopt_camera *camera, const double a[3], const double b[3], const double c[3],
                              double texels_per_unit, double max_zoom);

/* Projects a world point to continuous viewport coordinates: screen[0] grows to the right in
 * pixels (pixel i covers [i, i + 1)), screen[1] grows downwards (row j covers [j, j + 1)),
 * *depth is the signed distance along N (larger = closer to the camera). */
void texopt_camera_project(const texopt_camera *camera, const double point[3], double screen[2], double *depth);

/* Where to look closer at a triangle larger than one window of side `side` (world units):
 * the centres of a grid of about side x side cells over the triangle's bounding box in the
 * camera's (R, U) frame (relative to C, as window_x0 and window_y0), kept where they lie in
 * the triangle, written as (x, y) pairs to centres; returns how many. The cells grow by 1.25
 * until the grid has at most max_centres cells, so at most that many are written. */
size_t texopt_camera_close_up_centres(const texopt_camera *camera, const double a[3], const double b[3],
                                      const double c[3], double side, size_t max_centres, double *centres);

#endif
