/* test_texel_share.c - charts that read the same texels (engine/stage2/texel_share.c) kept sharing
 * them through stage 2 (meshwise.h, opt.share) and the budget (budget.h on the grouped
 * view).
 *
 * Each mesh is a primary chart (an n x n grid over a 40 x 40 texel square) and a second
 * chart far away in 3D: mirrored onto the same texels, repeated on them, tessellated
 * differently over them, or covering only half of them. The two charts want different
 * sizes (0.5 and 0.9 of their input), so untied they would drift apart. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "budget.h"
#include "coverage.h"
#include "distortion.h"
#include "handmesh.h"
#include "meshwise.h"
#include "test.h"
#include "texel_share.h"

#define SIZE 40.0  /* texels a side of the primary's square */
#define ORIGIN 8.0 /* its lower corner */
#define PRIMARY_N 5

typedef enum second_kind { MIRRORED, REPEATED, RETRIANGULATED, MIRRORED_RETRIANGULATED, HALF_SHIFTED } second_kind;

/* An n x n grid of chart `chart` over the square at (x0, ORIGIN), starting at vertex *v and
 * triangle *t. reversed: the UV triangles wind the other way (a mirrored part); jitter
 * moves inner vertices by up to jitter cells; z places the surface in 3D. */
static void add_grid(texopt_mesh *m, size_t *v, size_t *t, uint32_t chart, int n, double x0, int reversed,
                     double jitter, double z)
{
    size_t v0 = *v;
    double cell = SIZE / n;
    unsigned state = 777u + (unsigned)n;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++, (*v)++) {
            int inner = i > 0 && i < n && j > 0 && j < n;
            state = state * 1103515245u + 12345u;
            double jx = inner ? jitter * cell * (((state >> 8) & 0xffff) / 65535.0 - 0.5) : 0.0;
            state = state * 1103515245u + 12345u;
            double jy = inner ? jitter * cell * (((state >> 8) & 0xffff) / 65535.0 - 0.5) : 0.0;
            m->texel[2 * *v] = x0 + i * cell + jx;
            m->texel[2 * *v + 1] = ORIGIN + j * cell + jy;
            m->position[3 * *v] = (reversed ? -1.0 : 1.0) * m->texel[2 * *v] / 16.0;
            m->position[3 * *v + 1] = m->texel[2 * *v + 1] / 16.0;
            m->position[3 * *v + 2] = z;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++, *t += 2) {
            uint32_t a = (uint32_t)(v0 + (size_t)j * (n + 1) + i), b = a + 1;
            uint32_t d = a + (uint32_t)(n + 1), e = d + 1;
            uint32_t forward[6] = {a, b, e, a, e, d}, backward[6] = {a, e, b, a, d, e};
            memcpy(m->triangle + 3 * *t, reversed ? backward : forward, sizeof forward);
            m->chart_of[*t] = m->chart_of[*t + 1] = chart;
        }
}

static int second_n(second_kind kind)
{
    return kind == RETRIANGULATED || kind == MIRRORED_RETRIANGULATED ? 7 : PRIMARY_N;
}

static texopt_mesh *pair_mesh(second_kind kind)
{
    int n2 = second_n(kind);
    size_t nv = (size_t)(PRIMARY_N + 1) * (PRIMARY_N + 1) + (size_t)(n2 + 1) * (n2 + 1);
    texopt_mesh *m = handmesh_alloc(nv, 2 * (size_t)PRIMARY_N * PRIMARY_N + 2 * (size_t)n2 * n2);
    m->chart_count = 2;
    size_t v = 0, t = 0;
    add_grid(m, &v, &t, 0, PRIMARY_N, ORIGIN, 0, 0.0, 0.0);
    add_grid(m, &v, &t, 1, n2, ORIGIN + (kind == HALF_SHIFTED ? SIZE / 2 : 0.0),
             kind == MIRRORED || kind == MIRRORED_RETRIANGULATED, n2 != PRIMARY_N ? 0.3 : 0.0, 5.0);
    handmesh_finish(m);
    return m;
}

/* Primary 0.5 of its input size, the second chart 0.9. */
static texopt_triangle_target *unlike_targets(const texopt_mesh *m)
{
    texopt_triangle_target *tg = calloc(m->triangle_count, sizeof *tg);
    for (size_t t = 0; t < m->triangle_count; t++) {
        double l = m->chart_of[t] == 0 ? 0.5 : 0.9;
        tg[t] = (texopt_triangle_target){.lambda1 = l, .lambda2 = l, .w_rotation = 1, .w_stretch = 1};
    }
    return tg;
}

/* Where input texel point p of the primary (chart 0) went under layout x: 0 when no
 * primary triangle holds p. */
static int through_primary(const texopt_mesh *m, const double *x, const double p[2], double q[2])
{
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangle + 3 * t;
        double w[3];
        if (m->chart_of[t] != 0 || !handmesh_barycentric(m, t, p, w))
            continue;
        for (int k = 0; k < 2; k++)
            q[k] = w[0] * x[2 * tri[0] + k] + w[1] * x[2 * tri[1] + k] + w[2] * x[2 * tri[2] + k];
        return 1;
    }
    return 0;
}

/* Largest distance of a second-chart vertex from where the primary took its input point. */
static double worst_secondary_offset(const texopt_mesh *m, const double *x)
{
    double worst = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (m->chart_of[t] != 1)
            continue;
        for (int j = 0; j < 3; j++) {
            uint32_t v = m->triangle[3 * t + j];
            double q[2];
            if (!through_primary(m, x, m->texel + 2 * v, q))
                return INFINITY;
            worst = fmax(worst, hypot(x[2 * v] - q[0], x[2 * v + 1] - q[1]));
        }
    }
    return worst;
}

/* Texel area of the primary's triangles under layout x. */
static double primary_area(const texopt_mesh *m, const double *x)
{
    double a = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++)
        if (m->chart_of[t] == 0)
            a += 0.5 * fabs(handmesh_doubled_area(x, m->triangle + 3 * t, 2));
    return a;
}

/* Stage 2 (with or without the sharing groups) then the budget at c_r 0.5 on the grouped
 * view: the packed layout, its cost and the stage-2 layout. */
static void solve_and_pack(const texopt_mesh *m, const texopt_texel_share *share, int sharing, double *solved,
                           double *packed, texopt_budget_result *br)
{
    texopt_triangle_target *tg = unlike_targets(m);
    texopt_meshwise_options mo = {.share = sharing ? share : NULL};
    texopt_meshwise_report rep;
    char err[256] = "";
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, &mo, solved, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.flipped, 0);
    texopt_coverage in;
    CHECK_OK(texopt_coverage_measure(m, NULL, &in, err, sizeof err), err);
    texopt_budget_request req = {.kind = TEXOPT_BUDGET_RELATIVE_COST,
                                 .relative_cost = 0.5,
                                 .input_cost = (double)in.covered_texels,
                                 .input_width = m->width,
                                 .input_height = m->height,
                                 .targets = tg,
                                 .keep_shape = sharing ? share->grouped : NULL};
    CHECK_OK(texopt_budget_fit(sharing ? &share->view : m, solved, &req, packed, br, err, sizeof err), err);
    CHECK_EQ_INT(texopt_count_flipped(m, packed), 0);
    free(tg);
}

/* The second chart shares the primary's texels: grouped, tied, solved onto the primary's
 * output (within 0.25 texel, though it wants other sizes) and packed with it, so the
 * primary alone covers about the whole cost; solved and packed apart (no sharing) it
 * covers about half. */
static void check_shared(second_kind kind)
{
    texopt_mesh *m = pair_mesh(kind);
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    CHECK_EQ_INT(share->secondary_count, 1);
    CHECK_EQ_INT(share->primary_of[0], 0);
    CHECK_EQ_INT(share->primary_of[1], 0);
    CHECK_EQ_INT(share->view.chart_count, 1);
    CHECK_EQ_INT(share->grouped[0], 1);
    CHECK_EQ_INT(share->tie_count, (size_t)(second_n(kind) + 1) * (second_n(kind) + 1));
    size_t n = 2 * m->vertex_count;
    double *solved = calloc(n, sizeof *solved), *packed = calloc(n, sizeof *packed);
    texopt_budget_result br;
    solve_and_pack(m, share, 1, solved, packed, &br);
    CHECK(worst_secondary_offset(m, solved) < 0.25);
    CHECK_NEAR(br.relative_cost, 0.5, 0.02); /* a small layout: the budget corrects to a texel */
    CHECK(primary_area(m, packed) > 0.85 * br.cost);
    solve_and_pack(m, share, 0, solved, packed, &br);
    CHECK(worst_secondary_offset(m, solved) > 1.0);
    CHECK(primary_area(m, packed) < 0.6 * br.cost);
    free(solved);
    free(packed);
    texopt_texel_share_destroy(share);
    texopt_mesh_destroy(m);
}

TEST(mirrored_chart_on_the_same_texels_keeps_sharing_them)
{
    check_shared(MIRRORED);
}

TEST(repeated_chart_on_the_same_texels_keeps_sharing_them)
{
    check_shared(REPEATED);
}

/* Its vertices are not the primary's: the ties hold them on the primary's triangles. */
TEST(differently_tessellated_chart_on_the_same_texels_keeps_sharing_them)
{
    check_shared(RETRIANGULATED);
    check_shared(MIRRORED_RETRIANGULATED);
}

/* Half the second chart lies off the primary: no group (its untied half could fold over
 * other texels of the primary), and the output has no overlap at all, as without sharing. */
TEST(partly_overlapping_chart_is_laid_out_apart_without_new_overlap)
{
    texopt_mesh *m = pair_mesh(HALF_SHIFTED);
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    CHECK_EQ_INT(share->secondary_count, 0);
    CHECK_EQ_INT(share->tie_count, 0);
    CHECK_EQ_INT(share->view.chart_count, 2);
    CHECK_EQ_INT(share->view.chart_of[m->triangle_count - 1], 1);
    texopt_coverage in;
    CHECK_OK(texopt_coverage_measure(m, NULL, &in, err, sizeof err), err);
    CHECK(in.overlap_texels > 600); /* 20 x 40 texels read twice */
    size_t n = 2 * m->vertex_count;
    double *solved = calloc(n, sizeof *solved), *packed = calloc(n, sizeof *packed);
    texopt_budget_result br;
    solve_and_pack(m, share, 1, solved, packed, &br);
    texopt_coverage out;
    texopt_coverage_options co = {.texel = packed, .width = br.width, .height = br.height};
    CHECK_OK(texopt_coverage_measure(m, &co, &out, err, sizeof err), err);
    CHECK_EQ_INT(out.overlap_texels, 0);
    free(solved);
    free(packed);
    texopt_texel_share_destroy(share);
    texopt_mesh_destroy(m);
}

/* Charts on texels of their own share nothing: no groups, the view is the mesh's charts. */
TEST(charts_on_their_own_texels_form_no_group)
{
    texopt_mesh *m = handmesh_alloc(2 * 36, 2 * 50);
    m->chart_count = 2;
    size_t v = 0, t = 0;
    add_grid(m, &v, &t, 0, PRIMARY_N, ORIGIN, 0, 0.0, 0.0);
    add_grid(m, &v, &t, 1, PRIMARY_N, ORIGIN + SIZE + 8.0, 0, 0.0, 0.0);
    handmesh_finish(m);
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    CHECK_EQ_INT(share->secondary_count, 0);
    for (size_t k = 0; k < m->triangle_count; k++)
        CHECK_EQ_INT(share->view.chart_of[k], m->chart_of[k]);
    texopt_texel_share_destroy(share);
    texopt_texel_share_destroy(NULL);
    texopt_mesh_destroy(m);
}

TEST(bad_meshes_are_refused)
{
    texopt_mesh *m = pair_mesh(REPEATED);
    m->chart_of[3] = 7;
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK(texopt_texel_share_create(&share, m, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(share == NULL && strstr(err, "chart 7") != NULL);
    m->chart_of[3] = 0;
    m->triangle[5] = (uint32_t)m->vertex_count;
    CHECK(texopt_texel_share_create(&share, m, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(share == NULL && strstr(err, "past vertex count") != NULL);
    CHECK(texopt_texel_share_create(NULL, m, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    texopt_mesh_destroy(m);
}

TEST(groups_of_another_mesh_are_refused_by_the_solve)
{
    texopt_mesh *m = pair_mesh(REPEATED);
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    m->chart_count = 3;
    m->chart_of[0] = 2;
    texopt_triangle_target *tg = unlike_targets(m);
    double *out = calloc(2 * m->vertex_count, sizeof *out);
    texopt_meshwise_options mo = {.share = share};
    CHECK(texopt_meshwise_solve(m, tg, NULL, &mo, out, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "sharing groups") != NULL);
    free(out);
    free(tg);
    texopt_texel_share_destroy(share);
    texopt_mesh_destroy(m);
}

/* Who pays for shared texels in a budget of covered texels (target_allocation.h `paid`): a
 * secondary's triangles pay nothing, so the paid area is the primary's, which is what the
 * input covers; a triangle wound against its chart (a fold's minority side) pays nothing;
 * charts on their own texels all pay. */
TEST(secondaries_and_fold_minorities_pay_nothing)
{
    texopt_mesh *m = pair_mesh(MIRRORED_RETRIANGULATED);
    texopt_texel_share *share = NULL;
    char err[256] = "";
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    double *paid = calloc(m->triangle_count, sizeof *paid);
    size_t free_riders = texopt_texel_share_paid(share, m, paid);
    CHECK_EQ_INT(free_riders, 2 * 7 * 7);
    double paid_area = 0, primary = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        CHECK(paid[t] == (m->chart_of[t] == 0 ? 1.0 : 0.0));
        paid_area += paid[t] * fabs(m->area_texel[t]);
        primary += m->chart_of[t] == 0 ? fabs(m->area_texel[t]) : 0.0;
    }
    texopt_coverage in;
    CHECK_OK(texopt_coverage_measure(m, NULL, &in, err, sizeof err), err);
    CHECK_NEAR(paid_area, SIZE * SIZE, 1e-6);
    CHECK_NEAR(paid_area, primary, 1e-9);
    CHECK(fabs(paid_area - (double)in.covered_texels) < 0.05 * SIZE * SIZE);
    texopt_texel_share_destroy(share);
    free(paid);
    texopt_mesh_destroy(m);

    m = pair_mesh(HALF_SHIFTED); /* no group: both charts pay, until one triangle folds */
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    paid = calloc(m->triangle_count, sizeof *paid);
    CHECK_EQ_INT(texopt_texel_share_paid(share, m, paid), 0);
    for (size_t t = 0; t < m->triangle_count; t++)
        CHECK(paid[t] == 1.0);
    m->chart_sign = malloc(m->chart_count);
    for (size_t c = 0; c < m->chart_count; c++)
        m->chart_sign[c] = (int8_t)(m->area_texel[0] > 0 ? 1 : -1);
    m->area_texel[3] = -m->area_texel[3];
    CHECK_EQ_INT(texopt_texel_share_paid(share, m, paid), 1);
    CHECK(paid[3] == 0.0 && paid[2] == 1.0);
    texopt_texel_share_destroy(share);
    free(paid);
    texopt_mesh_destroy(m);
}
