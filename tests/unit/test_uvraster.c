/* test_uvraster.c - one-ring rasterisation into input texel positions. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "mesh.h"
#include "test.h"
#include "uvraster.h"

/* The world point seen at the centre of pixel (i, j). */
static void pixel_to_world(const texopt_camera *cam, int i, int j, double out[3])
{
    double pix = cam->window_side / cam->size;
    double x = cam->window_x0 + (i + 0.5) * pix;
    double y = cam->window_y0 + cam->window_side - (j + 0.5) * pix;
    for (int k = 0; k < 3; k++)
        out[k] = cam->center[k] + x * cam->right[k] + y * cam->up[k];
}

/* Barycentric coordinates of 2D point p in triangle (a, b, c). */
static void barycentric2(const double *a, const double *b, const double *c, const double *p, double w[3])
{
    double d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    w[1] = ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) / d;
    w[2] = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / d;
    w[0] = 1.0 - w[1] - w[2];
}

TEST(uvraster_texel_positions_match_the_surface_point)
{
    char err[256] = "";
    texopt_model *model = fixture_grid(4, 64, "flat");
    CHECK(model);
    texopt_mesh *mesh = NULL;
    texopt_uvraster *r = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&r, 64, err, sizeof err), err);
    /* Quad (1, 1), its first triangle: an interior triangle with a full one-ring. */
    uint32_t t = 2 * (1 * 4 + 1);
    CHECK_OK(texopt_uvraster_render(r, mesh, t, err, sizeof err), err);
    size_t covered = 0;
    int own = 0;
    for (int j = 0; j < 64; j++)
        for (int i = 0; i < 64; i++) {
            size_t q = (size_t)j * 64 + (size_t)i;
            if (r->face[q] < 0)
                continue;
            covered++;
            own += r->face[q] == (int32_t)t;
            double w[3];
            pixel_to_world(&r->camera, i, j, w);
            /* Grid: position (x, y, 0), UV (x, y), 64 x 64 texels. */
            CHECK_NEAR(r->texel[2 * q], 64.0 * w[0], 1e-9);
            CHECK_NEAR(r->texel[2 * q + 1], 64.0 * w[1], 1e-9);
        }
    CHECK_EQ_INT(covered, r->covered);
    CHECK(own > 100); /* the triangle itself is well visible */
    /* The one-ring of an interior grid triangle: three stars of 6 triangles, each edge's two
     * triangles counted twice, the triangle itself three times: 18 - 6 + 1 = 13 triangles
     * of area 1/32. Coverage in pixels is area / pixel area up to the rasterised border. */
    double pix = r->camera.window_side / 64.0;
    double expected = 13.0 / 32.0 / (pix * pix);
    CHECK(fabs((double)covered - expected) < 0.05 * expected);
    texopt_uvraster_destroy(r);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(uvraster_each_face_uses_its_own_uvs_across_a_seam)
{
    char err[256] = "";
    texopt_model *model = fixture_cube_with_seams(64);
    CHECK(model);
    texopt_mesh *mesh = NULL;
    texopt_uvraster *r = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&r, 32, err, sizeof err), err);
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        CHECK_OK(texopt_uvraster_render(r, mesh, t, err, sizeof err), err);
        CHECK(r->covered > 0);
        for (int j = 0; j < 32; j++)
            for (int i = 0; i < 32; i++) {
                size_t q = (size_t)j * 32 + (size_t)i;
                int32_t f = r->face[q];
                if (f < 0)
                    continue;
                /* The texel position lies inside the covering face's own UV triangle and
                 * matches the barycentrics of the 3D point seen there. */
                const uint32_t *tri = mesh->triangle + 3 * (size_t)f;
                double world[3], w[3];
                pixel_to_world(&r->camera, i, j, world);
                barycentric2(mesh->texel + 2 * tri[0], mesh->texel + 2 * tri[1], mesh->texel + 2 * tri[2],
                             r->texel + 2 * q, w);
                CHECK(w[0] > -1e-9 && w[1] > -1e-9 && w[2] > -1e-9);
                double p[3] = {0, 0, 0};
                for (int k = 0; k < 3; k++)
                    for (int d = 0; d < 3; d++)
                        p[d] += w[k] * mesh->position[3 * (size_t)mesh->point_of[tri[k]] + d];
                /* Seen along the normal: the in-plane coordinates agree. */
                for (int d = 0; d < 3; d++)
                    if (fabs(r->camera.normal[d]) < 0.5)
                        CHECK_NEAR(p[d], world[d], 1e-9);
            }
    }
    texopt_uvraster_destroy(r);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

/* Triangle 0 in z = 0 and two faces sharing its corner 0: face 1 hovers above it (z = 0.5)
 * with its far corners at hover[0..3] (x, y), face 2 lies below it (z = -0.5). */
static texopt_model *hover_model(const float hover[4])
{
    const float pos[] = {0,    0,        0,        1,    0, 0, 0, 1,    0,    0,     0,    0,    hover[0], hover[1],
                         0.5f, hover[2], hover[3], 0.5f, 0, 0, 0, 0.5f, 0.1f, -0.5f, 0.1f, 0.5f, -0.5f};
    const float uv[] = {0.0f, 0.0f, 0.3f, 0.0f, 0.0f, 0.3f, 0.5f, 0.5f, 0.8f,
                        0.5f, 0.5f, 0.8f, 0.0f, 0.6f, 0.3f, 0.6f, 0.0f, 0.9f};
    const uint32_t tris[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    return fixture_model_from_arrays(pos, uv, 9, tris, 3, 64, 64, "flat");
}

/* Renders triangle 0's one-ring with face 1 hovering at `hover`: seen[f] pixels show face f,
 * inside[k] pixel centres lie inside face k's projection, and shown_inside_both[f] of those
 * inside both show face f. Checks that face 1 shows wherever it lies beyond triangle 0. */
static void rasterise_hover(const float hover[4], int seen[3], int inside[2], int shown_inside_both[3])
{
    texopt_model *model = hover_model(hover);
    CHECK(model);
    char err[256] = "";
    texopt_mesh *mesh = NULL;
    texopt_uvraster *r = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&r, 64, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_render(r, mesh, 0, err, sizeof err), err);
    double s[2][3][2], depth;
    for (int f = 0; f < 2; f++)
        for (int k = 0; k < 3; k++) {
            const uint32_t *tri = mesh->triangle + 3 * f;
            texopt_camera_project(&r->camera, texopt_mesh_vertex_point(mesh, tri[k]), s[f][k], &depth);
        }
    memset(seen, 0, 3 * sizeof *seen);
    memset(inside, 0, 2 * sizeof *inside);
    memset(shown_inside_both, 0, 3 * sizeof *shown_inside_both);
    for (int j = 0; j < 64; j++)
        for (int i = 0; i < 64; i++) {
            size_t q = (size_t)j * 64 + (size_t)i;
            if (r->face[q] >= 0)
                seen[r->face[q]]++;
            double p[2] = {i + 0.5, j + 0.5}, w[2][3];
            int in[2];
            for (int f = 0; f < 2; f++) {
                barycentric2(s[f][0], s[f][1], s[f][2], p, w[f]);
                in[f] = w[f][0] > 1e-6 && w[f][1] > 1e-6 && w[f][2] > 1e-6;
                inside[f] += in[f];
            }
            if (in[0] && in[1] && r->face[q] >= 0)
                shown_inside_both[r->face[q]]++;
            if (in[1] && !in[0])
                CHECK_EQ_INT(r->face[q], 1);
        }
    texopt_uvraster_destroy(r);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

TEST(uvraster_closest_face_wins)
{
    /* The hovering face hides under 20% of triangle 0, so depth decides everywhere. */
    const float small_hover[4] = {0.3f, 0.05f, 0.05f, 0.3f};
    int seen[3] = {0}, inside[2] = {0}, shown[3] = {0};
    rasterise_hover(small_hover, seen, inside, shown);
    CHECK(inside[1] > 50);
    CHECK(inside[1] < inside[0] / 5);
    CHECK_EQ_INT(shown[1], inside[1]); /* the face above wins wherever it lies */
    CHECK(seen[0] > 50);
    CHECK_EQ_INT(seen[2], 0);
}

TEST(a_triangle_its_ring_hides_is_drawn_on_top)
{
    /* A bulge: the hovering face hides about half of triangle 0. Stage 1 would judge triangle 0
     * on the few pixels left, so it is drawn over its ring; where the hovering face lies
     * beyond it, that face still shows, and the face below stays hidden. */
    const float large_hover[4] = {0.9f, 0.3f, 0.3f, 0.9f};
    int seen[3] = {0}, inside[2] = {0}, shown[3] = {0};
    rasterise_hover(large_hover, seen, inside, shown);
    CHECK(shown[0] + shown[1] > inside[0] / 3); /* the faces overlap over a third of it */
    CHECK_EQ_INT(shown[1], 0);
    CHECK(seen[0] >= inside[0]);
    CHECK(seen[1] > 50);
    CHECK_EQ_INT(seen[2], 0);
}

TEST(uvraster_rejects_bad_arguments)
{
    char err[256] = "";
    texopt_uvraster *r = NULL;
    CHECK(texopt_uvraster_create(&r, 1, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(r == NULL);
    texopt_model *model = fixture_textured_quad(16, "flat");
    texopt_mesh *mesh = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&r, 16, err, sizeof err), err);
    CHECK(texopt_uvraster_render(r, mesh, 2, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(err[0] != '\0');
    texopt_uvraster_destroy(r);
    texopt_uvraster_destroy(NULL);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

/* Screen distance from the centre of pixel q to triangle t's projection: 0 inside (by its
 * barycentric coordinates), else to the nearest edge. */
static double pixel_distance_to_triangle(const texopt_uvraster *r, const texopt_mesh *mesh, uint32_t t, size_t q)
{
    double s[3][2], z;
    for (int k = 0; k < 3; k++) {
        uint32_t v = mesh->triangle[3 * (size_t)t + k];
        texopt_camera_project(&r->camera, mesh->position + 3 * (size_t)mesh->point_of[v], s[k], &z);
    }
    double p[2] = {(double)(q % (size_t)r->size) + 0.5, (double)(q / (size_t)r->size) + 0.5};
    double w[3];
    barycentric2(s[0], s[1], s[2], p, w);
    if (w[0] >= 0 && w[1] >= 0 && w[2] >= 0)
        return 0.0;
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        const double *a = s[k], *b = s[(k + 1) % 3];
        double e[2] = {b[0] - a[0], b[1] - a[1]};
        double u = fmin(1, fmax(0, ((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / (e[0] * e[0] + e[1] * e[1])));
        best = fmin(best, hypot(p[0] - a[0] - u * e[0], p[1] - a[1] - u * e[1]));
    }
    return best;
}

/* A fixture_grid(8, tex_size, "half") mesh and two 64-pixel rasters of it: `whole` never
 * drops a covered pixel (max_covered 0), `other` has create's defaults. */
typedef struct raster_pair {
    texopt_model *model;
    texopt_mesh *mesh;
    texopt_uvraster *whole, *other;
} raster_pair;

static int raster_pair_open(raster_pair *p, int tex_size)
{
    char err[256] = "";
    memset(p, 0, sizeof *p);
    p->model = fixture_grid(8, tex_size, "half");
    if (!p->model || texopt_mesh_create(&p->mesh, p->model, 0, err, sizeof err) != TEXOPT_OK ||
        texopt_uvraster_create(&p->whole, 64, err, sizeof err) != TEXOPT_OK ||
        texopt_uvraster_create(&p->other, 64, err, sizeof err) != TEXOPT_OK)
        return 0;
    p->whole->max_covered = 0;
    return 1;
}

static void raster_pair_close(raster_pair *p)
{
    texopt_uvraster_destroy(p->whole);
    texopt_uvraster_destroy(p->other);
    texopt_mesh_destroy(p->mesh);
    texopt_model_destroy(p->model);
}

TEST(a_narrowed_window_keeps_the_pixels_nearest_the_triangle)
{
    char err[256] = "";
    /* 32 texels per quad: the paper's window shows these rings at about 2 texels per pixel,
     * the limited window is filled by the ring edge to edge. */
    raster_pair pair;
    CHECK(raster_pair_open(&pair, 256));
    const texopt_mesh *mesh = pair.mesh;
    texopt_uvraster *whole = pair.whole, *kept = pair.other;
    CHECK_EQ_INT(kept->max_covered, TEXOPT_UVRASTER_MAX_COVERED);
    uint32_t t = 2 * (3 * 8 + 5);
    CHECK_OK(texopt_uvraster_render(whole, mesh, t, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_render(kept, mesh, t, err, sizeof err), err);
    CHECK(whole->covered > 2 * kept->max_covered);
    CHECK(kept->covered <= kept->max_covered);
    CHECK(kept->covered > kept->max_covered - 64); /* only a ring of equal distances lost */
    size_t counted = 0;
    int own_whole = 0, own_kept = 0;
    double farthest_kept = 0, nearest_dropped = INFINITY;
    for (size_t q = 0; q < 64 * 64; q++) {
        own_whole += whole->face[q] == (int32_t)t;
        own_kept += kept->face[q] == (int32_t)t;
        if (kept->face[q] >= 0) {
            counted++;
            CHECK_EQ_INT(kept->face[q], whole->face[q]);
            CHECK(kept->texel[2 * q] == whole->texel[2 * q]);
            CHECK(kept->texel[2 * q + 1] == whole->texel[2 * q + 1]);
        } else {
            CHECK(kept->texel[2 * q] == 0 && kept->texel[2 * q + 1] == 0);
        }
        if (whole->face[q] < 0)
            continue;
        double d = pixel_distance_to_triangle(kept, mesh, t, q);
        if (kept->face[q] >= 0)
            farthest_kept = fmax(farthest_kept, d);
        else
            nearest_dropped = fmin(nearest_dropped, d);
    }
    CHECK_EQ_INT(counted, kept->covered);
    CHECK(own_kept > 100);
    CHECK_EQ_INT(own_kept, own_whole);
    /* Nearest to rounding: mirror-image pixels may differ in the last bits of a distance. */
    CHECK(farthest_kept <= nearest_dropped + 1e-9);
    CHECK(farthest_kept > 5.0);
    raster_pair_close(&pair);
}

TEST(a_ring_under_the_zoom_limit_is_rasterised_whole)
{
    char err[256] = "";
    raster_pair pair;
    CHECK(raster_pair_open(&pair, 64));
    const texopt_mesh *mesh = pair.mesh;
    texopt_uvraster *whole = pair.whole, *small = pair.other;
    small->max_covered = 16; /* far below any ring's coverage: must not apply here */
    for (uint32_t t = 0; t < mesh->triangle_count; t += 5) {
        CHECK_OK(texopt_uvraster_render(whole, mesh, t, err, sizeof err), err);
        CHECK_OK(texopt_uvraster_render(small, mesh, t, err, sizeof err), err);
        CHECK(small->covered > 16);
        CHECK_EQ_INT(small->covered, whole->covered);
        CHECK(memcmp(small->face, whole->face, 64 * 64 * sizeof *whole->face) == 0);
        CHECK(memcmp(small->texel, whole->texel, 2 * 64 * 64 * sizeof *whole->texel) == 0);
    }
    raster_pair_close(&pair);
}

TEST(a_close_up_window_shows_part_of_a_large_triangle)
{
    char err[256] = "";
    /* The unit quad over 512 texels: triangle 0 (corners (0,0), (1,0), (1,1)) spans 512
     * texels, its own window about 8 texels a pixel. A 64-texel window inside it, 0.1 units
     * right of the centroid, shows one texel a pixel. */
    texopt_model *model = fixture_textured_quad(512, "flat");
    CHECK(model);
    texopt_mesh *mesh = NULL;
    texopt_uvraster *r = NULL;
    CHECK_OK(texopt_mesh_create(&mesh, model, 0, err, sizeof err), err);
    CHECK_OK(texopt_uvraster_create(&r, 64, err, sizeof err), err);
    double side = 64.0 / 512.0, window[3] = {0.1 - 0.5 * side, -0.5 * side, side};
    CHECK_OK(texopt_uvraster_render_window(r, mesh, 0, window, err, sizeof err), err);
    CHECK(r->camera.window_side == side);
    CHECK(r->camera.window_x0 == window[0] && r->camera.window_y0 == window[1]);
    /* The triangle covers the window edge to edge; the pixels nearest the centre stay. */
    CHECK_EQ_INT(r->covered, r->max_covered);
    size_t counted = 0;
    double farthest_kept = 0, nearest_dropped = INFINITY;
    for (int j = 0; j < 64; j++)
        for (int i = 0; i < 64; i++) {
            size_t q = (size_t)j * 64 + (size_t)i;
            double d = hypot(i + 0.5 - 32.0, j + 0.5 - 32.0);
            if (r->face[q] < 0) {
                nearest_dropped = fmin(nearest_dropped, d);
                continue;
            }
            counted++;
            farthest_kept = fmax(farthest_kept, d);
            CHECK_EQ_INT(r->face[q], 0);
            /* UV = (x, y) on this quad: the texel is 512 times the surface point. */
            double p[3];
            pixel_to_world(&r->camera, i, j, p);
            CHECK_NEAR(r->texel[2 * q], 512.0 * p[0], 1e-6);
            CHECK_NEAR(r->texel[2 * q + 1], 512.0 * p[1], 1e-6);
        }
    CHECK_EQ_INT(counted, r->covered);
    CHECK(farthest_kept <= nearest_dropped + 1e-9);
    double bad[3][3] = {{0, 0, 0}, {0, 0, -1}, {NAN, 0, 0.1}};
    for (int k = 0; k < 3; k++)
        CHECK(texopt_uvraster_render_window(r, mesh, 0, bad[k], err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(texopt_uvraster_render_window(r, mesh, 2, window, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_uvraster_destroy(r);
    texopt_mesh_destroy(mesh);
    texopt_model_destroy(model);
}

/* Sun et al. appendix A: the window is the box of the triangle's own corners in (R, U), its
 * short side padded on both sides to a square; the one-ring drawn into it spills over. */
TEST(the_paper_window_frames_the_triangle_corners)
{
    char err[256] = "";
    raster_pair pair;
    CHECK(raster_pair_open(&pair, 64));
    texopt_uvraster *paper = pair.whole, *ring = pair.other;
    paper->paper_window = 1;
    paper->max_zoom = 0.0;
    ring->max_zoom = 0.0;
    int wider = 0;
    for (uint32_t t = 0; t < pair.mesh->triangle_count; t += 7) {
        CHECK_OK(texopt_uvraster_render(paper, pair.mesh, t, err, sizeof err), err);
        CHECK_OK(texopt_uvraster_render(ring, pair.mesh, t, err, sizeof err), err);
        const texopt_camera *cam = &paper->camera;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++) {
            const double *p = texopt_mesh_vertex_point(pair.mesh, pair.mesh->triangle[3 * (size_t)t + (size_t)k]);
            double d[3] = {p[0] - cam->center[0], p[1] - cam->center[1], p[2] - cam->center[2]};
            double xy[2] = {d[0] * cam->right[0] + d[1] * cam->right[1] + d[2] * cam->right[2],
                            d[0] * cam->up[0] + d[1] * cam->up[1] + d[2] * cam->up[2]};
            for (int i = 0; i < 2; i++)
                lo[i] = fmin(lo[i], xy[i]), hi[i] = fmax(hi[i], xy[i]);
        }
        double w = hi[0] - lo[0], h = hi[1] - lo[1], side = fmax(w, h);
        CHECK_NEAR(cam->window_side, side, 2e-6 * side);
        CHECK_NEAR(cam->window_x0, lo[0] - 0.5 * (side - w), 2e-6 * side);
        CHECK_NEAR(cam->window_y0, lo[1] - 0.5 * (side - h), 2e-6 * side);
        CHECK(ring->camera.window_side >= cam->window_side);
        wider += ring->camera.window_side > 1.5 * cam->window_side;
    }
    CHECK(wider > 0); /* the one-ring's window is the wider one */
    raster_pair_close(&pair);
}
