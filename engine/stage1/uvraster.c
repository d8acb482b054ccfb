/* uvraster.c - rasterises a triangle's one-ring into input texel positions (Sun et al. 2022,
 * section 4.1.1 and appendix A, with the render-once reformulation of DESIGN.md 3.1).
 *
 * It does not sample textures or evaluate losses (triloss.c). */
#include "uvraster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

texopt_status texopt_uvraster_create(texopt_uvraster **out, int size, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "uvraster: NULL output");
    *out = NULL;
    if (size < 2 || size > 4096)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "uvraster: viewport size %d outside [2, 4096]",
                           size);
    texopt_uvraster *r = calloc(1, sizeof *r);
    size_t n = (size_t)size * (size_t)size;
    if (r) {
        r->size = size;
        r->max_zoom = TEXOPT_CAMERA_MAX_ZOOM;
        r->max_covered = TEXOPT_UVRASTER_MAX_COVERED;
        r->texel = calloc(2 * n, sizeof *r->texel);
        r->face = malloc(n * sizeof *r->face);
        r->depth = malloc(n * sizeof *r->depth);
        r->nearest = malloc(n * sizeof *r->nearest);
    }
    if (!r || !r->texel || !r->face || !r->depth || !r->nearest) {
        texopt_uvraster_destroy(r);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "uvraster: out of memory for %dx%d", size, size);
    }
    *out = r;
    return TEXOPT_OK;
}

void texopt_uvraster_destroy(texopt_uvraster *raster)
{
    if (!raster)
        return;
    free(raster->texel);
    free(raster->face);
    free(raster->depth);
    free(raster->nearest);
    free(raster->ring);
    free(raster->ring_points);
    free(raster);
}

/* Fetches the one-ring into raster->ring, growing the scratch when a larger ring appears. */
static texopt_status gather_one_ring(texopt_uvraster *r, const texopt_mesh *mesh, uint32_t triangle, size_t *count,
                                     char *err, size_t err_len)
{
    size_t n = texopt_mesh_one_ring(mesh, triangle, r->ring, r->ring_cap);
    if (n > r->ring_cap) {
        size_t cap = n + 16;
        uint32_t *ring = realloc(r->ring, cap * sizeof *ring);
        if (!ring)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "uvraster: one-ring of %zu", n);
        r->ring = ring;
        double *points = realloc(r->ring_points, 9 * cap * sizeof *points);
        if (!points)
            return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "uvraster: one-ring of %zu", n);
        r->ring_points = points;
        r->ring_cap = cap;
        n = texopt_mesh_one_ring(mesh, triangle, r->ring, r->ring_cap);
    }
    *count = n;
    return TEXOPT_OK;
}

static void clear_buffer(texopt_uvraster *r)
{
    size_t n = (size_t)r->size * (size_t)r->size;
    memset(r->texel, 0, 2 * n * sizeof *r->texel);
    for (size_t i = 0; i < n; i++) {
        r->face[i] = -1;
        r->depth[i] = -INFINITY;
    }
    r->covered = 0;
}

/* Rasterises one face: every pixel centre inside its projection (edges inclusive) whose depth
 * is strictly closer than what is there (on_top: whatever is there) takes the face's
 * interpolated texel position. Returns the pixels it took. */
static size_t rasterise_face(texopt_uvraster *r, const texopt_mesh *mesh, uint32_t face, int on_top)
{
    double s[3][2], z[3], t[3][2];
    for (int k = 0; k < 3; k++) {
        uint32_t v = mesh->triangle[3 * (size_t)face + k];
        texopt_camera_project(&r->camera, texopt_mesh_vertex_point(mesh, v), s[k], &z[k]);
        t[k][0] = mesh->texel[2 * (size_t)v];
        t[k][1] = mesh->texel[2 * (size_t)v + 1];
    }
    double area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[2][0] - s[0][0]) * (s[1][1] - s[0][1]);
    /* Seen edge-on it covers no pixel centre in a stable way; its neighbours cover the area. */
    if (!(fabs(area) > 1e-12))
        return 0;
    double inv = 1.0 / area;
    double xmin = fmin(s[0][0], fmin(s[1][0], s[2][0]));
    double xmax = fmax(s[0][0], fmax(s[1][0], s[2][0]));
    double ymin = fmin(s[0][1], fmin(s[1][1], s[2][1]));
    double ymax = fmax(s[0][1], fmax(s[1][1], s[2][1]));
    int i0 = (int)fmax(0.0, ceil(xmin - 0.5)), i1 = (int)fmin(r->size - 1.0, floor(xmax - 0.5));
    int j0 = (int)fmax(0.0, ceil(ymin - 0.5)), j1 = (int)fmin(r->size - 1.0, floor(ymax - 0.5));
    const double tol = -1e-9;
    size_t taken = 0;
    for (int j = j0; j <= j1; j++) {
        double y = j + 0.5;
        for (int i = i0; i <= i1; i++) {
            double x = i + 0.5;
            double w0 = ((s[1][0] - x) * (s[2][1] - y) - (s[2][0] - x) * (s[1][1] - y)) * inv;
            double w1 = ((s[2][0] - x) * (s[0][1] - y) - (s[0][0] - x) * (s[2][1] - y)) * inv;
            double w2 = 1.0 - w0 - w1;
            if (w0 < tol || w1 < tol || w2 < tol)
                continue;
            size_t q = (size_t)j * (size_t)r->size + (size_t)i;
            double depth = w0 * z[0] + w1 * z[1] + w2 * z[2];
            if (!on_top && !(depth > r->depth[q]))
                continue;
            taken++;
            if (r->face[q] < 0)
                r->covered++;
            r->depth[q] = depth;
            r->face[q] = (int32_t)face;
            r->texel[2 * q] = w0 * t[0][0] + w1 * t[1][0] + w2 * t[2][0];
            r->texel[2 * q + 1] = w0 * t[0][1] + w1 * t[1][1] + w2 * t[2][1];
        }
    }
    return taken;
}

/* Texels per world unit over the one-ring: its texel area over its 3D area. */
static double ring_texels_per_unit(const texopt_uvraster *r, const texopt_mesh *mesh, size_t n)
{
    double texel = 0.0, world = 0.0;
    for (size_t f = 0; f < n; f++) {
        texel += fabs(mesh->area_texel[r->ring[f]]);
        world += mesh->area_3d[r->ring[f]];
    }
    return world > 0.0 ? sqrt(texel / world) : 0.0;
}

/* Squared distance from (x, y) to the triangle s: 0 inside (either orientation), else to
 * the nearest edge. */
static double distance2_to_triangle(const double s[3][2], double x, double y)
{
    double best = INFINITY;
    int negative = 0, positive = 0;
    for (int k = 0; k < 3; k++) {
        const double *a = s[k], *b = s[(k + 1) % 3];
        double ex = b[0] - a[0], ey = b[1] - a[1], px = x - a[0], py = y - a[1];
        double cross = ex * py - ey * px;
        negative |= cross < 0.0;
        positive |= cross > 0.0;
        double len2 = ex * ex + ey * ey;
        double t = len2 > 0.0 ? fmin(fmax((px * ex + py * ey) / len2, 0.0), 1.0) : 0.0;
        double dx = px - t * ex, dy = py - t * ey;
        best = fmin(best, dx * dx + dy * dy);
    }
    return negative && positive ? best : 0.0;
}

/* The k-th smallest (0-based) of v[0..n), k < n; reorders v. Hoare selection with the
 * middle element as pivot: linear on average, deterministic. */
static double kth_smallest(double *v, size_t n, size_t k)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, want = (ptrdiff_t)k;
    while (lo < hi) {
        double pivot = v[lo + (hi - lo) / 2];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                double t = v[i];
                v[i++] = v[j];
                v[j--] = t;
            }
        }
        if (want <= j)
            hi = j;
        else if (want >= i)
            lo = i;
        else
            return v[want]; /* between the two parts: equal to the pivot */
    }
    return v[want];
}

/* Uncovers the covered pixels at or past distance `cut` (kept: strictly nearer, and the
 * pixels at distance 0) whose squared distances r->depth holds. */
static void uncover_from(texopt_uvraster *r, double cut)
{
    size_t px = (size_t)r->size * (size_t)r->size;
    for (size_t q = 0; q < px; q++) {
        if (r->face[q] < 0 || r->depth[q] < cut || r->depth[q] == 0.0)
            continue;
        r->face[q] = -1;
        r->texel[2 * q] = r->texel[2 * q + 1] = 0.0;
        r->covered--;
    }
}

/* Uncovers all but the max_covered covered pixels nearest the viewport's centre: a close-up
 * window lies inside its triangle, which covers it edge to edge. Ties at one distance are
 * broken by the pixel's index, so exactly max_covered stay. */
static void keep_pixels_nearest_centre(texopt_uvraster *r)
{
    if (r->max_covered == 0 || r->covered <= r->max_covered)
        return;
    size_t px = (size_t)r->size * (size_t)r->size, n = 0;
    double c = 0.5 * r->size;
    for (size_t q = 0; q < px; q++) {
        if (r->face[q] < 0)
            continue;
        double x = (double)(q % (size_t)r->size) + 0.5 - c, y = (double)(q / (size_t)r->size) + 0.5 - c;
        r->depth[q] = x * x + y * y + 1e-9 * (double)(q + 1);
        r->nearest[n++] = r->depth[q];
    }
    uncover_from(r, kth_smallest(r->nearest, n, r->max_covered));
}

/* Uncovers all but the max_covered covered pixels nearest the triangle (uvraster.h). The
 * depth buffer, no longer needed, holds each covered pixel's squared distance. */
static void keep_nearest_pixels(texopt_uvraster *r, const texopt_mesh *mesh, uint32_t triangle)
{
    if (r->max_covered == 0 || r->covered <= r->max_covered)
        return;
    const uint32_t *tri = mesh->triangle + 3 * (size_t)triangle;
    double s[3][2], z;
    for (int k = 0; k < 3; k++)
        texopt_camera_project(&r->camera, texopt_mesh_vertex_point(mesh, tri[k]), s[k], &z);
    size_t px = (size_t)r->size * (size_t)r->size, n = 0;
    for (size_t q = 0; q < px; q++) {
        if (r->face[q] < 0)
            continue;
        double x = (double)(q % (size_t)r->size) + 0.5, y = (double)(q / (size_t)r->size) + 0.5;
        r->depth[q] = r->face[q] == (int32_t)triangle ? 0.0 : distance2_to_triangle(s, x, y);
        r->nearest[n++] = r->depth[q];
    }
    /* Keep what is strictly nearer than the first pixel past the budget: at most max_covered
     * stay (more only if the triangle itself covers more), and pixels at one distance go
     * together unless rounding tells them apart. */
    uncover_from(r, kth_smallest(r->nearest, n, r->max_covered));
}

/* Gathers the one-ring of `triangle`, with its corners' 3D points, and builds the paper's
 * camera on it (before any narrowing); *n receives the ring's face count. */
static texopt_status ring_camera(texopt_uvraster *raster, const texopt_mesh *mesh, uint32_t triangle, size_t *n,
                                 char *err, size_t err_len)
{
    if (!raster || !mesh)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "uvraster: NULL argument");
    if (triangle >= mesh->triangle_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "uvraster: triangle %u past triangle count %zu",
                           triangle, mesh->triangle_count);
    texopt_status st = gather_one_ring(raster, mesh, triangle, n, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    for (size_t f = 0; f < *n; f++)
        for (int k = 0; k < 3; k++)
            memcpy(raster->ring_points + 9 * f + 3 * k,
                   texopt_mesh_vertex_point(mesh, mesh->triangle[3 * (size_t)raster->ring[f] + k]), 3 * sizeof(double));
    const uint32_t *tri = mesh->triangle + 3 * (size_t)triangle;
    st = texopt_camera_create(&raster->camera, texopt_mesh_vertex_point(mesh, tri[0]),
                              texopt_mesh_vertex_point(mesh, tri[1]), texopt_mesh_vertex_point(mesh, tri[2]),
                              raster->ring_points, raster->paper_window ? 0 : 3 * *n, raster->size, err, err_len);
    if (st != TEXOPT_OK)
        return texopt_fail(err, err_len, st, "uvraster: triangle %u is degenerate in 3D", triangle);
    return TEXOPT_OK;
}

static size_t pixels_of_face(const texopt_uvraster *r, uint32_t face)
{
    size_t n = 0, all = (size_t)r->size * (size_t)r->size;
    for (size_t q = 0; q < all; q++)
        n += r->face[q] == (int32_t)face;
    return n;
}

/* The one-ring by depth, then the triangle itself over it where ring faces in front hide more
 * than TEXOPT_UVRASTER_HIDDEN_SHARE of its pixels: stage 1 judges the triangle, and a bulge
 * seen from behind its own face (Duck's pupils: 73 of a triangle's 93 pixels) would leave it
 * judged on what it hardly shows, so it could shrink to lambda_min unseen. */
static void rasterise_ring(texopt_uvraster *raster, const texopt_mesh *mesh, size_t n)
{
    clear_buffer(raster);
    /* ring[0] is the triangle (texopt_mesh_one_ring): on the empty buffer it takes every
     * pixel centre inside it. */
    uint32_t triangle = raster->ring[0];
    size_t own = rasterise_face(raster, mesh, triangle, 0);
    for (size_t f = 1; f < n; f++)
        rasterise_face(raster, mesh, raster->ring[f], 0);
    if (!raster->paper_window &&
        (double)pixels_of_face(raster, triangle) < (1.0 - TEXOPT_UVRASTER_HIDDEN_SHARE) * (double)own)
        rasterise_face(raster, mesh, triangle, 1);
}

texopt_status texopt_uvraster_render(texopt_uvraster *raster, const texopt_mesh *mesh, uint32_t triangle, char *err,
                                     size_t err_len)
{
    size_t n = 0;
    texopt_status st = ring_camera(raster, mesh, triangle, &n, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    const uint32_t *tri = mesh->triangle + 3 * (size_t)triangle;
    double paper_side = raster->camera.window_side;
    texopt_camera_limit_zoom(&raster->camera, texopt_mesh_vertex_point(mesh, tri[0]),
                             texopt_mesh_vertex_point(mesh, tri[1]), texopt_mesh_vertex_point(mesh, tri[2]),
                             ring_texels_per_unit(raster, mesh, n), raster->max_zoom);
    rasterise_ring(raster, mesh, n);
    if (raster->camera.window_side < paper_side)
        keep_nearest_pixels(raster, mesh, triangle);
    return TEXOPT_OK;
}

texopt_status texopt_uvraster_render_window(texopt_uvraster *raster, const texopt_mesh *mesh, uint32_t triangle,
                                            const double window[3], char *err, size_t err_len)
{
    if (!window || !(window[2] > 0.0) || !isfinite(window[0] + window[1] + window[2]))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "uvraster: bad window");
    size_t n = 0;
    texopt_status st = ring_camera(raster, mesh, triangle, &n, err, err_len);
    if (st != TEXOPT_OK)
        return st;
    raster->camera.window_x0 = window[0];
    raster->camera.window_y0 = window[1];
    raster->camera.window_side = window[2];
    rasterise_ring(raster, mesh, n);
    keep_pixels_nearest_centre(raster);
    return TEXOPT_OK;
}
