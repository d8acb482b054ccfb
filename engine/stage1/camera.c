/* camera.c - builds the per-triangle orthographic camera of Sun et al. 2022, appendix A.
 *
 * Only geometry: a frame (C, R, U, N) and a square window fitted to the one-ring, or
 * narrowed to a zoom the caller measured. It does not rasterise (uvraster.c), and never
 * touches textures: the texel density comes from the caller. */
#include "camera.h"

#include <math.h>

#include "vec3.h"

static void sub3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

/* A point's coordinates in the camera's (R, U) frame, relative to C. */
static void frame_point(const texopt_camera *camera, const double p[3], double out[2])
{
    double d[3];
    sub3(p, camera->center, d);
    out[0] = texopt_dot3(d, camera->right);
    out[1] = texopt_dot3(d, camera->up);
}

/* Grows the (R, U) bounding box by one point. */
static void include_point(const texopt_camera *camera, const double p[3], double box[4])
{
    double xy[2];
    frame_point(camera, p, xy);
    double x = xy[0], y = xy[1];
    if (x < box[0])
        box[0] = x;
    if (y < box[1])
        box[1] = y;
    if (x > box[2])
        box[2] = x;
    if (y > box[3])
        box[3] = y;
}

/* Pads the bounding box on its short side, symmetrically, so the window is square: the
 * whole one-ring stays visible and pixels stay square. A hair of margin keeps vertices on the
 * window border inside the last pixel. */
static void fit_square_window(texopt_camera *camera, const double box[4])
{
    double w = box[2] - box[0], h = box[3] - box[1];
    double side = (w > h ? w : h) * (1.0 + 1e-6);
    camera->window_side = side;
    camera->window_x0 = 0.5 * (box[0] + box[2]) - 0.5 * side;
    camera->window_y0 = 0.5 * (box[1] + box[3]) - 0.5 * side;
}

texopt_status texopt_camera_create(texopt_camera *camera, const double a[3], const double b[3], const double c[3],
                                   const double *ring_points, size_t point_count, int size, char *err, size_t err_len)
{
    if (!camera || !a || !b || !c || (point_count > 0 && !ring_points))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "camera: NULL argument");
    if (size < 2)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "camera: viewport size %d is below 2", size);
    for (int k = 0; k < 3; k++)
        camera->center[k] = (a[k] + b[k] + c[k]) / 3.0;
    double ab[3], ac[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    texopt_cross3(ab, ac, camera->normal);
    sub3(a, camera->center, camera->right);
    if (!texopt_normalize3(camera->normal) || !texopt_normalize3(camera->right))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "camera: degenerate triangle has no normal");
    texopt_cross3(camera->normal, camera->right, camera->up);
    camera->size = size;

    double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    include_point(camera, a, box);
    include_point(camera, b, box);
    include_point(camera, c, box);
    for (size_t i = 0; i < point_count; i++)
        include_point(camera, ring_points + 3 * i, box);
    if (!(box[2] - box[0] > 0.0) || !isfinite(box[2] - box[0] + box[3] - box[1]))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "camera: one-ring has no extent on screen");
    fit_square_window(camera, box);
    return TEXOPT_OK;
}

double texopt_camera_zoom(const texopt_camera *camera, double texels_per_unit)
{
    return texels_per_unit * camera->window_side / camera->size;
}

/* The window's left (or bottom) edge for a side `side` along one axis: centred on the
 * centroid (0), then moved into the range that keeps the triangle [t0, t1] and stays within
 * the paper's window [w0, w0 + wide]; that range is never empty because side covers
 * [t0, t1] and [t0, t1] lies in the paper's window. */
static double narrowed_edge(double side, double t0, double t1, double w0, double wide)
{
    double lo = fmax(t1 - side, w0), hi = fmin(t0, w0 + wide - side);
    return fmin(fmax(-0.5 * side, lo), hi);
}

void texopt_camera_limit_zoom(texopt_camera *camera, const double a[3], const double b[3], const double c[3],
                              double texels_per_unit, double max_zoom)
{
    if (!(max_zoom > 0.0) || !(texels_per_unit > 0.0) || !isfinite(texels_per_unit))
        return;
    double side = max_zoom * camera->size / texels_per_unit;
    double tri[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    include_point(camera, a, tri);
    include_point(camera, b, tri);
    include_point(camera, c, tri);
    side = fmax(side, fmax(tri[2] - tri[0], tri[3] - tri[1]) * (1.0 + 1e-6));
    if (!(side < camera->window_side))
        return;
    camera->window_x0 = narrowed_edge(side, tri[0], tri[2], camera->window_x0, camera->window_side);
    camera->window_y0 = narrowed_edge(side, tri[1], tri[3], camera->window_y0, camera->window_side);
    camera->window_side = side;
}

void texopt_camera_project(const texopt_camera *camera, const double point[3], double screen[2], double *depth)
{
    double d[3];
    sub3(point, camera->center, d);
    double scale = camera->size / camera->window_side;
    screen[0] = (texopt_dot3(d, camera->right) - camera->window_x0) * scale;
    screen[1] = (camera->window_y0 + camera->window_side - texopt_dot3(d, camera->up)) * scale;
    if (depth)
        *depth = texopt_dot3(d, camera->normal);
}

/* Inside or on the border of the triangle t, either orientation. */
static int in_triangle(const double t[3][2], double x, double y)
{
    int negative = 0, positive = 0;
    for (int k = 0; k < 3; k++) {
        const double *p = t[k], *q = t[(k + 1) % 3];
        double cross = (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
        negative |= cross < 0.0;
        positive |= cross > 0.0;
    }
    return !(negative && positive);
}

size_t texopt_camera_close_up_centres(const texopt_camera *camera, const double a[3], const double b[3],
                                      const double c[3], double side, size_t max_centres, double *centres)
{
    if (!(side > 0.0) || max_centres == 0)
        return 0;
    double t[3][2], box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    frame_point(camera, a, t[0]);
    frame_point(camera, b, t[1]);
    frame_point(camera, c, t[2]);
    include_point(camera, a, box);
    include_point(camera, b, box);
    include_point(camera, c, box);
    double w = box[2] - box[0], h = box[3] - box[1];
    if (!isfinite(w + h))
        return 0;
    double cell = side, cells_x, cells_y;
    for (;;) { /* counted in doubles: a tiny side must not overflow a size_t */
        cells_x = fmax(1.0, ceil(w / cell));
        cells_y = fmax(1.0, ceil(h / cell));
        if (cells_x * cells_y <= (double)max_centres)
            break;
        cell *= 1.25;
    }
    size_t nx = (size_t)cells_x, ny = (size_t)cells_y;
    size_t count = 0;
    for (size_t i = 0; i < nx; i++)
        for (size_t j = 0; j < ny; j++) {
            double x = box[0] + ((double)i + 0.5) * w / (double)nx;
            double y = box[1] + ((double)j + 0.5) * h / (double)ny;
            if (!in_triangle(t, x, y))
                continue;
            centres[2 * count] = x;
            centres[2 * count + 1] = y;
            count++;
        }
    return count;
}
