/* test_meshwise.c - the mesh-wise local-global solve (engine/stage2/meshwise.c) on generated grids.
 *
 * Meshes are built by hand (texopt_mesh filled directly) so that each test controls the
 * layout exactly: jittered grids, two charts, mirrored charts, degenerate triangles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "distortion.h"
#include "handmesh.h"
#include "meshwise.h"
#include "test.h"

#define PI 3.14159265358979323846

/* `charts` side-by-side n x n grids of cell `cell` texels, vertices jittered by up to
 * jitter * cell (deterministic), one chart each. */
static texopt_mesh *grid_mesh(int n, double cell, double jitter, int charts)
{
    size_t per_v = (size_t)(n + 1) * (n + 1), per_t = 2 * (size_t)n * n;
    texopt_mesh *m = handmesh_alloc(per_v * charts, per_t * charts);
    m->chart_count = (size_t)charts;
    unsigned state = 12345;
    for (int c = 0; c < charts; c++) {
        double x0 = c * (n + 4) * cell;
        for (int j = 0; j <= n; j++)
            for (int i = 0; i <= n; i++) {
                size_t v = per_v * c + (size_t)j * (n + 1) + i;
                state = state * 1103515245u + 12345u;
                double jx = jitter * cell * (((state >> 8) & 0xffff) / 65535.0 - 0.5);
                state = state * 1103515245u + 12345u;
                double jy = jitter * cell * (((state >> 8) & 0xffff) / 65535.0 - 0.5);
                m->texel[2 * v] = x0 + i * cell + jx;
                m->texel[2 * v + 1] = j * cell + jy;
                m->position[3 * v] = m->texel[2 * v] / 16.0;
                m->position[3 * v + 1] = m->texel[2 * v + 1] / 16.0;
            }
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                size_t t = per_t * c + 2 * ((size_t)j * n + i);
                uint32_t a = (uint32_t)(per_v * c + (size_t)j * (n + 1) + i);
                uint32_t b = a + 1, d = a + (uint32_t)(n + 1), e = d + 1;
                uint32_t tris[6] = {a, b, e, a, e, d};
                memcpy(m->triangle + 3 * t, tris, sizeof tris);
                m->chart_of[t] = m->chart_of[t + 1] = (uint32_t)c;
            }
    }
    handmesh_finish(m);
    return m;
}

static texopt_triangle_target *uniform_targets(size_t n, double l1, double l2, double alpha, double beta, double w_r,
                                               double w_s)
{
    texopt_triangle_target *t = calloc(n, sizeof *t);
    for (size_t i = 0; i < n; i++) {
        t[i].lambda1 = l1;
        t[i].lambda2 = l2;
        t[i].alpha = alpha;
        t[i].beta = beta;
        t[i].w_rotation = w_r;
        t[i].w_stretch = w_s;
    }
    return t;
}

/* Jacobian of triangle t from the input layout to `out`, as [a b; c d]. */
static void jacobian_of(const texopt_mesh *m, const double *out, size_t t, double J[4])
{
    const uint32_t *tri = m->triangle + 3 * t;
    double e[4], f[4]; /* columns: edges 1 and 2 */
    for (int r = 0; r < 2; r++) {
        e[2 * r] = m->texel[2 * tri[1] + r] - m->texel[2 * tri[0] + r];
        e[2 * r + 1] = m->texel[2 * tri[2] + r] - m->texel[2 * tri[0] + r];
        f[2 * r] = out[2 * tri[1] + r] - out[2 * tri[0] + r];
        f[2 * r + 1] = out[2 * tri[2] + r] - out[2 * tri[0] + r];
    }
    double det = e[0] * e[3] - e[1] * e[2];
    double inv[4] = {e[3] / det, -e[1] / det, -e[2] / det, e[0] / det};
    J[0] = f[0] * inv[0] + f[1] * inv[2];
    J[1] = f[0] * inv[1] + f[1] * inv[3];
    J[2] = f[2] * inv[0] + f[3] * inv[2];
    J[3] = f[2] * inv[1] + f[3] * inv[3];
}

static double rotation_degrees(const double J[4])
{
    return atan2(J[2] - J[1], J[0] + J[3]) * 180.0 / PI;
}

static int energies_non_increasing(const texopt_meshwise_report *r)
{
    if (r->energy_count > 0 && r->energy[0] > r->energy_initial * (1 + 1e-12) + 1e-12)
        return 0;
    for (int i = 1; i < r->energy_count; i++)
        if (r->energy[i] > r->energy[i - 1] * (1 + 1e-12) + 1e-12)
            return 0;
    return 1;
}

TEST(identity_targets_keep_the_layout)
{
    texopt_mesh *m = grid_mesh(10, 8.0, 0.4, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    double worst = 0.0;
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        worst = fmax(worst, fabs(out[i] - m->texel[i]));
    CHECK_NEAR(worst, 0.0, 1e-6);
    CHECK_EQ_INT(rep.flipped, 0);
    CHECK_NEAR(rep.energy_final, 0.0, 1e-9);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(uniform_half_scale_quarters_every_area)
{
    texopt_mesh *m = grid_mesh(12, 8.0, 0.4, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * t, 2) / m->area_texel[t];
        CHECK_NEAR(ratio, 0.25, 0.0025);
    }
    CHECK(rep.iterations > 1);
    CHECK(energies_non_increasing(&rep));
    CHECK(rep.energy_final < 1e-6 * rep.energy_initial);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(anisotropic_target_shrinks_along_its_axis)
{
    texopt_mesh *m = grid_mesh(10, 8.0, 0.3, 1);
    /* lambda1 = 0.4 along V(beta) e1: with beta = 0 that is the texel x axis. */
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.4, 1.0, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double J[4];
        jacobian_of(m, out, t, J);
        CHECK_NEAR(J[0], 0.4, 0.01);
        CHECK_NEAR(J[3], 1.0, 0.01);
        CHECK_NEAR(J[1], 0.0, 0.01);
        CHECK_NEAR(J[2], 0.0, 0.01);
    }
    /* beta = 45 degrees: the shrink is along the diagonal, J = V diag(0.4, 1) V^T. */
    free(tg);
    tg = uniform_targets(m->triangle_count, 0.4, 1.0, 0, PI / 4, 1, 1);
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    double J[4];
    jacobian_of(m, out, 7, J);
    CHECK_NEAR(J[0], 0.7, 0.01);
    CHECK_NEAR(J[1], -0.3, 0.01);
    CHECK_NEAR(J[2], -0.3, 0.01);
    CHECK_NEAR(J[3], 0.7, 0.01);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(rotation_target_rotates_only_when_weighted)
{
    texopt_mesh *m = grid_mesh(8, 8.0, 0.3, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, 30 * PI / 180, 0, 100, 1);
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double J[4];
        jacobian_of(m, out, t, J);
        CHECK_NEAR(rotation_degrees(J), 30.0, 0.5);
        CHECK_NEAR(J[0] * J[3] - J[1] * J[2], 1.0, 0.01);
    }
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t].w_rotation = 0.0;
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double J[4];
        jacobian_of(m, out, t, J);
        CHECK_NEAR(rotation_degrees(J), 0.0, 1e-6);
    }
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(rotation_target_uses_the_ninety_degree_symmetry)
{
    texopt_mesh *m = grid_mesh(8, 8.0, 0.3, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    texopt_meshwise_report rep;
    /* A quarter turn is the texel grid's own symmetry: it costs nothing, nothing moves. */
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, PI / 2, 0, 100, 1);
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_NEAR(rep.energy_final, 0.0, 1e-9);
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        CHECK_NEAR(out[i], m->texel[i], 1e-6);
    /* 60 degrees is reached more cheaply as -30 (k = 3) than as +60. */
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t].alpha = 60 * PI / 180;
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    double J[4];
    jacobian_of(m, out, 5, J);
    CHECK_NEAR(rotation_degrees(J), -30.0, 0.5);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(conflicting_targets_never_flip)
{
    texopt_mesh *m = grid_mesh(16, 8.0, 0.45, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, 0, 0, 1, 1);
    unsigned s = 99;
    for (size_t t = 0; t < m->triangle_count; t++) {
        int quad = (int)(t / 2), qi = quad % 16, qj = quad / 16;
        double l = ((qi / 2 + qj / 2) % 2) ? 0.05 : 1.0; /* 2x2-quad checkerboard */
        s = s * 1103515245u + 12345u;
        tg[t].lambda1 = l;
        tg[t].lambda2 = l * (0.5 + 0.5 * ((s >> 8) & 0xff) / 255.0);
        s = s * 1103515245u + 12345u;
        tg[t].alpha = ((s >> 8) & 0xffff) / 65536.0 * PI / 2;
        s = s * 1103515245u + 12345u;
        tg[t].beta = ((s >> 8) & 0xffff) / 65536.0 * PI / 2;
        tg[t].w_rotation = 50.0;
        tg[t].w_stretch = 50.0;
    }
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    texopt_meshwise_options opt = {.max_iterations = 100, .tolerance = 1e-7};
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &opt, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.flipped, 0);
    CHECK_EQ_INT(texopt_count_flipped(m, out), 0);
    double min_det = INFINITY;
    for (size_t t = 0; t < m->triangle_count; t++) {
        double J[4];
        jacobian_of(m, out, t, J);
        min_det = fmin(min_det, J[0] * J[3] - J[1] * J[2]);
    }
    CHECK(min_det > 0.0);
    CHECK(energies_non_increasing(&rep));
    CHECK(rep.energy_final < rep.energy_initial);
    CHECK(rep.energy_count == rep.iterations);
    CHECK(rep.factorizations > 2); /* the barrier was active: this test exercises it */
    /* Two threads (u and v systems factorised in parallel) give the same layout. */
    double *out2 = calloc(2 * m->vertex_count, sizeof *out2);
    opt.threads = 2;
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &opt, out2, NULL, NULL, err, sizeof err), err);
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        CHECK_NEAR(out2[i], out[i], 1e-9 * (1 + fabs(out[i])));
    free(out2);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(two_charts_keep_their_own_translation)
{
    texopt_mesh *m = grid_mesh(6, 8.0, 0.2, 2);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), err);
    size_t per_t = m->triangle_count / 2;
    for (int c = 0; c < 2; c++) {
        /* The pinned vertex is the first vertex of the chart's first triangle. */
        uint32_t pin = m->triangle[3 * per_t * c];
        CHECK_NEAR(out[2 * pin], m->texel[2 * pin], 1e-9);
        CHECK_NEAR(out[2 * pin + 1], m->texel[2 * pin + 1], 1e-9);
        double J[4];
        jacobian_of(m, out, per_t * c + 3, J);
        CHECK_NEAR(J[0], 0.5, 1e-4);
        CHECK_NEAR(J[3], 0.5, 1e-4);
    }
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(mirrored_chart_stays_mirrored_and_unflipped)
{
    texopt_mesh *m = grid_mesh(6, 8.0, 0.2, 1);
    for (size_t v = 0; v < m->vertex_count; v++)
        m->texel[2 * v] = 200.0 - m->texel[2 * v]; /* mirror the layout, not the surface */
    handmesh_finish(m);
    CHECK(m->area_texel[0] < 0.0);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.flipped, 0);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * t, 2) / m->area_texel[t];
        CHECK_NEAR(ratio, 0.25, 0.0025); /* same sign: still mirrored */
    }
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(degenerate_triangles_are_carried_through)
{
    /* Grid plus a zero-area texel sliver on three collinear grid vertices and a second copy
     * of interior triangle 28; both copies of 28 are flagged 3D-degenerate the way mesh.c
     * flags a face of zero 3D area (they keep their texel area, so only the barrier holds
     * them). */
    texopt_mesh *g = grid_mesh(6, 8.0, 0.0, 1);
    texopt_mesh *m = handmesh_alloc(g->vertex_count, g->triangle_count + 2);
    memcpy(m->texel, g->texel, 2 * g->vertex_count * sizeof(double));
    memcpy(m->position, g->position, 3 * g->vertex_count * sizeof(double));
    memcpy(m->triangle, g->triangle, 3 * g->triangle_count * sizeof(uint32_t));
    size_t T = g->triangle_count;
    uint32_t sliver[3] = {0, 1, 2}; /* collinear along the bottom row */
    memcpy(m->triangle + 3 * T, sliver, sizeof sliver);
    memcpy(m->triangle + 3 * (T + 1), g->triangle + 3 * 28, 3 * sizeof(uint32_t));
    handmesh_finish(m);
    m->flags[T + 1] |= TEXOPT_TRI_DEGENERATE_3D; /* as mesh.c flags a 3D-degenerate face */
    m->flags[28] |= TEXOPT_TRI_DEGENERATE_3D;    /* interior: its vertices have fitted neighbours */
    CHECK(m->flags[T] & TEXOPT_TRI_DEGENERATE_UV);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        CHECK(isfinite(out[i]));
    CHECK_EQ_INT(rep.flipped, 0);
    /* The degenerate face's vertices moved with their neighbours (the whole grid halves). */
    double J[4];
    jacobian_of(m, out, 28, J);
    CHECK_NEAR(J[0], 0.5, 1e-3);
    CHECK_NEAR(J[3], 0.5, 1e-3);
    free(out);
    free(tg);
    texopt_mesh_destroy(g);
    texopt_mesh_destroy(m);
}

TEST(bad_input_is_refused_with_a_message)
{
    texopt_mesh *m = grid_mesh(3, 8.0, 0.0, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    tg[4].lambda1 = NAN;
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "triangle 4") != NULL);
    tg[4].lambda1 = 1.0;
    tg[2].w_stretch = -1.0;
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    tg[2].w_stretch = 1.0;
    /* A starting layout with a flipped triangle. */
    double *start = malloc(2 * m->vertex_count * sizeof *start);
    memcpy(start, m->texel, 2 * m->vertex_count * sizeof *start);
    start[2 * 5] += 20.0; /* vertex 5 (interior) pushed across its neighbours */
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, start, NULL, out, NULL, NULL, err, sizeof err),
                 TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "flipped") != NULL);
    CHECK_EQ_INT(texopt_meshwise_solve(NULL, tg, NULL, NULL, out, NULL, NULL, err, sizeof err),
                 TEXOPT_E_INVALID_ARGUMENT);
    texopt_meshwise_options negative = {.max_iterations = -1};
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, NULL, &negative, out, NULL, NULL, err, sizeof err),
                 TEXOPT_E_INVALID_ARGUMENT);
    /* A triangle naming a vertex past the count. */
    m->triangle[7] = (uint32_t)m->vertex_count;
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, NULL, err, sizeof err), TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "past vertex count") != NULL);
    free(start);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

static void count_progress(void *user, const texopt_progress *p)
{
    int *calls = user;
    if (strcmp(p->stage, "stage2") == 0 && p->stage_fraction > 0.0 && p->stage_fraction <= 1.0)
        (*calls)++;
}

TEST(progress_is_reported_and_cancel_stops)
{
    texopt_mesh *m = grid_mesh(6, 8.0, 0.2, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    int calls = 0;
    atomic_int cancel = 0;
    texopt_monitor mon = {count_progress, &calls, &cancel};
    texopt_meshwise_report rep;
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, &mon, err, sizeof err), err);
    CHECK_EQ_INT(calls, rep.iterations);
    atomic_store(&cancel, 1);
    CHECK_EQ_INT(texopt_meshwise_solve(m, tg, NULL, NULL, out, NULL, &mon, err, sizeof err), TEXOPT_E_CANCELED);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(zero_stretch_weights_still_follow_a_consistent_target)
{
    /* Stage 1 gives w_S = 0 where the loss ignores the stretch (flat colour); the target
     * (area-driven) must still be reached, through the weight floor. */
    texopt_mesh *m = grid_mesh(6, 8.0, 0.2, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 0, 0);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    texopt_meshwise_options opt = {.max_iterations = 250, .tolerance = 1e-12};
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &opt, out, NULL, NULL, err, sizeof err), err);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * t, 2) / m->area_texel[t];
        CHECK_NEAR(ratio, 0.25, 0.0025);
    }
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(a_mesh_without_triangles_is_returned_unchanged)
{
    texopt_mesh *m = handmesh_alloc(3, 0);
    for (int i = 0; i < 6; i++)
        m->texel[i] = i * 1.5;
    texopt_triangle_target tg[1] = {{0}};
    double out[6] = {0};
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    for (int i = 0; i < 6; i++)
        CHECK_NEAR(out[i], i * 1.5, 0.0);
    CHECK_EQ_INT(rep.flipped, 0);
    texopt_mesh_destroy(m);
}

/* A folded chart: the right half of the surface is the mirror image of the left half in 3D
 * and reuses its UVs (as mirrored models do), joined to it along the fold column x = 0. Its
 * triangles have negative texel area; the chart is one connected piece. */
static texopt_mesh *folded_mesh(int n, double cell, double shift)
{
    size_t per_row = 2 * (size_t)n + 1; /* left columns 0..n, right columns 1..n */
    texopt_mesh *m = handmesh_alloc(per_row * (n + 1), 4 * (size_t)n * n);
    for (int j = 0; j <= n; j++)
        for (int c = 0; c < (int)per_row; c++) {
            size_t v = (size_t)j * per_row + c;
            int mirrored_i = c <= n ? c : 2 * n - c; /* UV column */
            /* shift > 0 moves the right half's inner vertices off the left half's ones:
             * a fold whose halves are not tessellated alike. */
            int inner = c > n && c < 2 * n;
            m->texel[2 * v] = (mirrored_i + (inner ? shift : 0.0)) * cell;
            m->texel[2 * v + 1] = (j + (inner && j > 0 && j < n ? 0.6 * shift : 0.0)) * cell;
            m->position[3 * v] = (c - n) * cell / 16.0;
            m->position[3 * v + 1] = j * cell / 16.0;
        }
    size_t t = 0;
    for (int j = 0; j < n; j++)
        for (int c = 0; c < 2 * n; c++, t += 2) {
            uint32_t a = (uint32_t)((size_t)j * per_row + c), b = a + 1;
            uint32_t d = a + (uint32_t)per_row, e = d + 1;
            uint32_t tris[6] = {a, b, e, a, e, d};
            memcpy(m->triangle + 3 * t, tris, sizeof tris);
        }
    handmesh_finish(m);
    return m;
}

TEST(folded_chart_keeps_its_halves_on_the_same_texels)
{
    int n = 5;
    texopt_mesh *m = folded_mesh(n, 8.0, 0.0);
    size_t per_row = 2 * (size_t)n + 1;
    CHECK(m->area_texel[0] > 0.0 && m->area_texel[m->triangle_count - 1] < 0.0);
    /* The halves want different sizes: left 0.5, right 0.9. */
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangle + 3 * t;
        if ((tri[0] % per_row) >= (size_t)n) /* right half */
            tg[t].lambda1 = tg[t].lambda2 = 0.9;
    }
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.flipped, 0);
    CHECK_EQ_INT(rep.merged_vertices, (n + 1) * n);
    CHECK_EQ_INT(rep.fold_ties, 0);
    for (int j = 0; j <= n; j++)
        for (int c = n + 1; c < (int)per_row; c++) {
            size_t right = (size_t)j * per_row + c, left = (size_t)j * per_row + (2 * n - c);
            CHECK_NEAR(out[2 * right], out[2 * left], 0.0);
            CHECK_NEAR(out[2 * right + 1], out[2 * left + 1], 0.0);
        }
    /* The shared layout is a compromise: between the two targets' areas. */
    double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * 6, 2) / m->area_texel[6];
    CHECK(ratio > 0.25 * 1.05 && ratio < 0.81 * 0.95);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

/* Output position of input point p through the layout, by the triangle of the left half of
 * a folded mesh containing p (brute force); 0 when none does. */
static int map_through_left_half(const texopt_mesh *m, const double *out, int n, const double p[2], double q[2])
{
    size_t per_row = 2 * (size_t)n + 1;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangle + 3 * t;
        double w[3];
        if (tri[0] % per_row >= (size_t)n || m->area_texel[t] <= 0.0 || !handmesh_barycentric(m, t, p, w))
            continue; /* right half, or not p's */
        for (int k = 0; k < 2; k++)
            q[k] = w[0] * out[2 * tri[0] + k] + w[1] * out[2 * tri[1] + k] + w[2] * out[2 * tri[2] + k];
        return 1;
    }
    return 0;
}

TEST(folded_chart_with_unlike_halves_stays_on_its_texels)
{
    int n = 5;
    texopt_mesh *m = folded_mesh(n, 8.0, 0.37);
    size_t per_row = 2 * (size_t)n + 1;
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    for (size_t t = 0; t < m->triangle_count; t++)
        if ((m->triangle[3 * t] % per_row) >= (size_t)n)
            tg[t].lambda1 = tg[t].lambda2 = 0.9;
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.flipped, 0);
    CHECK(energies_non_increasing(&rep));
    size_t checked = 0;
    for (int j = 0; j <= n; j++)
        for (int c = n + 1; c < 2 * n; c++) {
            size_t v = (size_t)j * per_row + c;
            double q[2];
            CHECK(map_through_left_half(m, out, n, m->texel + 2 * v, q));
            /* The halves disagree by several texels untied; tied, by < 0.1 texel. */
            CHECK_NEAR(out[2 * v], q[0], 0.1);
            CHECK_NEAR(out[2 * v + 1], q[1], 0.1);
            checked++;
        }
    CHECK_EQ_INT(checked, (size_t)(n + 1) * (n - 1));
    /* The inner right columns are tied; the outer column merges exactly. */
    CHECK_EQ_INT(rep.fold_ties, (n - 1) * (n + 1));
    CHECK_EQ_INT(rep.merged_vertices, n + 1);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(squeezed_start_recovers_and_the_barrier_weight_drops)
{
    /* Start at 0.2x the input (det 0.04, deep inside the barrier's zone below 0.5) with
     * identity targets: the barrier dominates at first, so eq. 28 must lower w_b, and the
     * layout must grow back to the input size. */
    texopt_mesh *m = grid_mesh(6, 8.0, 0.2, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 1, 1, 0, 0, 1, 1);
    double *start = malloc(2 * m->vertex_count * sizeof *start);
    for (size_t i = 0; i < 2 * m->vertex_count; i++)
        start[i] = 0.2 * m->texel[i];
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_report rep;
    char err[256] = "";
    texopt_meshwise_options opt = {.barrier_weight = 1.0, .max_iterations = 100};
    CHECK_OK(texopt_meshwise_solve(m, tg, start, &opt, out, &rep, NULL, err, sizeof err), err);
    CHECK(rep.barrier_weight_final <= 1.0 / 20.0);
    CHECK(energies_non_increasing(&rep));
    for (size_t t = 0; t < m->triangle_count; t++) {
        double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * t, 2) / m->area_texel[t];
        CHECK_NEAR(ratio, 1.0, 0.01);
    }
    free(start);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(fit_weight_sets_how_fast_targets_pull)
{
    /* S moves w_S / (w_S + w_rs) of the way to its target per iteration: with w_rs = 1e4 five
     * iterations barely move the layout, with the default w_rs = 1 they nearly reach it. */
    texopt_mesh *m = grid_mesh(4, 8.0, 0.2, 1);
    texopt_triangle_target *tg = uniform_targets(m->triangle_count, 0.5, 0.5, 0, 0, 1, 1);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    char err[256] = "";
    texopt_meshwise_options stiff = {.max_iterations = 5, .tolerance = 1e-12, .fit_weight = 1e4};
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &stiff, out, NULL, NULL, err, sizeof err), err);
    double ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * 3, 2) / m->area_texel[3];
    CHECK(ratio > 0.99);
    texopt_meshwise_options plain = {.max_iterations = 5, .tolerance = 1e-12};
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &plain, out, NULL, NULL, err, sizeof err), err);
    ratio = 0.5 * handmesh_doubled_area(out, m->triangle + 3 * 3, 2) / m->area_texel[3];
    CHECK(ratio < 0.3);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}
