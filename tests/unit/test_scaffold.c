/* test_scaffold.c - bijective stage 2 with scaffold triangles (engine/layout/scaffold.c).
 *
 * Charts are unions of square cells (two triangles each) on a lattice, built by hand, with
 * targets that push them into each other or into themselves: without the scaffold the
 * solved layout covers texel centres twice, with it never. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chart_unfold.h"
#include "distortion.h"
#include "handmesh.h"
#include "meshwise.h"
#include "scaffold.h"
#include "target_restate.h"
#include "test.h"
#include "texel_share.h"

#define CELL 4.0

typedef struct cell {
    int i, j;
    uint32_t chart;
} cell;

/* A mesh of the given cells; lattice vertices are shared by the cells of one chart. */
static texopt_mesh *cell_mesh(const cell *cells, size_t n, size_t charts, int lattice)
{
    size_t side = (size_t)lattice + 1;
    uint32_t *id = malloc(side * side * charts * sizeof *id);
    for (size_t k = 0; k < side * side * charts; k++)
        id[k] = UINT32_MAX;
    size_t nv = 0;
    for (size_t c = 0; c < n; c++)
        for (int dj = 0; dj < 2; dj++)
            for (int di = 0; di < 2; di++) {
                size_t key = (cells[c].chart * side + (size_t)(cells[c].j + dj)) * side + (size_t)(cells[c].i + di);
                if (id[key] == UINT32_MAX)
                    id[key] = (uint32_t)nv++;
            }
    texopt_mesh *m = handmesh_alloc(nv, 2 * n);
    m->chart_count = charts;
    m->width = m->height = (int)(CELL * lattice) + 64;
    for (size_t k = 0; k < side * side * charts; k++)
        if (id[k] != UINT32_MAX) {
            size_t i = k % side, j = (k / side) % side;
            m->texel[2 * id[k]] = CELL * (double)i;
            m->texel[2 * id[k] + 1] = CELL * (double)j;
            m->position[3 * id[k]] = (double)i;
            m->position[3 * id[k] + 1] = (double)j;
        }
    for (size_t c = 0; c < n; c++) {
        uint32_t v[4];
        for (int k = 0; k < 4; k++)
            v[k] = id[(cells[c].chart * side + (size_t)(cells[c].j + k / 2)) * side + (size_t)(cells[c].i + k % 2)];
        uint32_t tris[6] = {v[0], v[1], v[3], v[0], v[3], v[2]};
        memcpy(m->triangle + 6 * c, tris, sizeof tris);
        m->chart_of[2 * c] = m->chart_of[2 * c + 1] = cells[c].chart;
    }
    free(id);
    handmesh_finish(m);
    return m;
}

static texopt_triangle_target stretch_target(double l1, double l2)
{
    texopt_triangle_target t = {0};
    t.lambda1 = l1;
    t.lambda2 = l2;
    t.w_stretch = 1.0;
    return t;
}

static double total_area(const texopt_mesh *m, const double *x)
{
    double s = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangle + 3 * t;
        const double *a = x + 2 * (size_t)v[0], *b = x + 2 * (size_t)v[1], *c = x + 2 * (size_t)v[2];
        s += 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    return s;
}

/* Two 4 x 4 charts one cell apart, each asked to grow 1.6 times: pinned at their lower left
 * corners, the left one grows into the right one. */
static texopt_mesh *two_charts(texopt_triangle_target **targets)
{
    cell cells[32];
    size_t n = 0;
    for (uint32_t c = 0; c < 2; c++)
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 4; i++)
                cells[n++] = (cell){i + 5 * (int)c, j, c};
    texopt_mesh *m = cell_mesh(cells, n, 2, 10);
    *targets = malloc(m->triangle_count * sizeof **targets);
    for (size_t t = 0; t < m->triangle_count; t++)
        (*targets)[t] = stretch_target(1.6, 1.6);
    return m;
}

TEST(charts_pushed_into_each_other_overlap_without_scaffold_and_not_with_it)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = two_charts(&tg);
    double *plain = malloc(2 * m->vertex_count * sizeof *plain), *bij = malloc(2 * m->vertex_count * sizeof *bij);
    char err[256];
    texopt_meshwise_report mr;
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, plain, &mr, NULL, err, sizeof err), err);
    size_t within, between;
    CHECK_OK(texopt_count_overlap(m, plain, &within, &between, err, sizeof err), err);
    CHECK_MSG(between > 20, "without scaffold: %zu texels shared between charts", between);

    texopt_scaffold_options so = {0};
    so.one_box = 1;
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, &so, bij, &rep, NULL, err, sizeof err), err);
    CHECK_OK(texopt_count_overlap(m, bij, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(between, 0);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(rep.charts_scaffolded, 2);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK(rep.triangles > 0);
    CHECK_EQ_INT(texopt_count_flipped(m, bij), 0);
    /* The charts still grew (the scaffold gives way): at least 1.5 times their area. */
    CHECK_MSG(total_area(m, bij) > 1.5 * total_area(m, m->texel), "area %g from %g", total_area(m, bij),
              total_area(m, m->texel));
    free(plain);
    free(bij);
    free(tg);
    texopt_mesh_destroy(m);
}

/* The same charts in a fixed box 1% larger than their bounding box (Liu et al. 2019's
 * bounded packing): they grow only into the gap and the margin, every vertex stays inside,
 * no centre is covered twice. With the default box (3x, rebuilt) they grow 1.5 times. */
TEST(a_fixed_box_holds_growing_charts_inside_it)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = two_charts(&tg);
    double *x = malloc(2 * m->vertex_count * sizeof *x);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < m->vertex_count; v++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], m->texel[2 * v + a]);
            hi[a] = fmax(hi[a], m->texel[2 * v + a]);
        }
    double pad[2] = {0.005 * (hi[0] - lo[0]), 0.005 * (hi[1] - lo[1])};
    double box[4] = {lo[0] - pad[0], lo[1] - pad[1], hi[0] + pad[0], hi[1] + pad[1]};
    texopt_scaffold_options so = {0};
    so.one_box = 1;
    so.box = box;
    texopt_scaffold_report rep;
    char err[256];
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, &so, x, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    size_t within, between, outside = 0;
    CHECK_OK(texopt_count_overlap(m, x, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(between, 0);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(texopt_count_flipped(m, x), 0);
    for (size_t v = 0; v < m->vertex_count; v++)
        outside += x[2 * v] < box[0] || x[2 * v] > box[2] || x[2 * v + 1] < box[1] || x[2 * v + 1] > box[3];
    CHECK_EQ_INT(outside, 0);
    double grown = total_area(m, x) / total_area(m, m->texel);
    CHECK_MSG(grown > 1.01 && grown < 1.3, "area grew %.3f times in the fixed box", grown);
    free(x);
    free(tg);
    texopt_mesh_destroy(m);
}

/* A U: two arms 2 cells wide and 6 high on a base row 5 cells wide, one cell apart. The
 * arms' triangles ask to be 2.5 times wider: they close the gap. */
static texopt_mesh *closing_u(texopt_triangle_target **targets)
{
    cell cells[64];
    size_t n = 0;
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < 5; i++)
            if (j == 0 || i != 2)
                cells[n++] = (cell){i, j, 0};
    texopt_mesh *m = cell_mesh(cells, n, 1, 8);
    *targets = malloc(m->triangle_count * sizeof **targets);
    for (size_t c = 0; c < n; c++)
        (*targets)[2 * c] = (*targets)[2 * c + 1] = stretch_target(cells[c].j > 0 ? 2.5 : 1.0, 1.0);
    return m;
}

TEST(a_chart_closing_on_itself_stays_bijective)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = closing_u(&tg);
    double *plain = malloc(2 * m->vertex_count * sizeof *plain), *bij = malloc(2 * m->vertex_count * sizeof *bij);
    char err[256];
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, plain, NULL, NULL, err, sizeof err), err);
    size_t within, between;
    CHECK_OK(texopt_count_overlap(m, plain, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "without scaffold: %zu texels covered twice", within);
    CHECK_EQ_INT(texopt_count_flipped(m, plain), 0); /* locally injective, globally not */

    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, NULL, bij, &rep, NULL, err, sizeof err), err);
    CHECK_OK(texopt_count_overlap(m, bij, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(rep.charts_scaffolded, 1);
    CHECK(rep.rounds >= 1);
    CHECK_EQ_INT(texopt_count_flipped(m, bij), 0);
    CHECK_MSG(total_area(m, bij) > 1.4 * total_area(m, m->texel), "area %g from %g", total_area(m, bij),
              total_area(m, m->texel));
    free(plain);
    free(bij);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(a_chart_overlapping_at_the_start_is_solved_without_scaffold)
{
    /* Two cells of one chart laid on the same texels (a fold): no scaffold can separate
     * them; the solve goes on and says so. */
    cell cells[] = {{0, 0, 0}, {1, 0, 0}, {3, 0, 1}};
    texopt_mesh *m = cell_mesh(cells, 3, 2, 6);
    /* fold the second cell back onto the first: its right edge moves to x = 0 */
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->texel[2 * v] == 2 * CELL && v < 6) /* vertices 4 and 5: chart 0's right edge */
            m->texel[2 * v] = 0.5 * CELL;
    handmesh_finish(m);
    texopt_triangle_target *tg = malloc(m->triangle_count * sizeof *tg);
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t] = stretch_target(1.0, 1.0);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    char err[256];
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 1);
    CHECK_EQ_INT(rep.charts_scaffolded, 1);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(meshwise_refuses_a_clockwise_scaffold_triangle)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = two_charts(&tg);
    double corner[2] = {-10, -10};
    uint32_t tri[3] = {0, 1, (uint32_t)m->vertex_count}; /* (0,0), (4,0), (-10,-10): clockwise */
    double rest[6] = {0, 0, 4, 0, -10, -10};
    texopt_meshwise_scaffold sc = {1, corner, 1, tri, rest, 0.01};
    texopt_meshwise_options o = {0};
    o.scaffold = &sc;
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    char err[256];
    CHECK(texopt_meshwise_solve(m, tg, NULL, &o, out, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    sc.weight = 0.0;
    tri[1] = (uint32_t)m->vertex_count; /* (0,0), (-10,-10), (4,0): counter-clockwise, no weight */
    tri[2] = 1;
    rest[2] = rest[3] = -10;
    rest[4] = 4;
    rest[5] = 0;
    CHECK(texopt_meshwise_solve(m, tg, NULL, &o, out, NULL, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

TEST(overlap_count_counts_shared_centres)
{
    /* Chart 1 is chart 0's 4 x 4 texel cell moved right by 2: 2 x 4 centres in both, less
     * the 2 + 2 on one of the two diagonals (on an edge: neither side's). */
    cell cells[] = {{0, 0, 0}, {0, 0, 1}};
    texopt_mesh *m = cell_mesh(cells, 2, 2, 2);
    for (size_t v = 0; v < m->vertex_count; v++)
        if (v >= 4) /* chart 1's */
            m->texel[2 * v] += 2.0;
    size_t within, between;
    char err[256];
    CHECK_OK(texopt_count_overlap(m, m->texel, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(between, 4);
    CHECK_EQ_INT(within, 0);
    texopt_mesh_destroy(m);
}

typedef struct progress_log {
    double last;
    int reports, backwards;
} progress_log;

static void log_progress(void *user, const texopt_progress *p)
{
    progress_log *log = user;
    log->backwards += p->stage_fraction < log->last;
    log->last = p->stage_fraction;
    log->reports++;
}

TEST(progress_runs_forward_through_the_re_meshes)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = closing_u(&tg);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    char err[256];
    progress_log log = {0};
    texopt_monitor mon = {log_progress, &log, NULL};
    texopt_scaffold_options so = {0};
    so.remesh_iterations = 3;
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, &so, out, &rep, &mon, err, sizeof err), err);
    CHECK(rep.rounds >= 2);
    CHECK(log.reports >= rep.meshwise.iterations);
    CHECK_EQ_INT(log.backwards, 0);
    CHECK(log.last <= 1.0);
    free(out);
    free(tg);
    texopt_mesh_destroy(m);
}

/* One chart of 8 x 2 cells, flat in 3D, laid in texels with a Z fold: column 5 runs back
 * (its triangles FLIPPED, 4 of 32) and columns 6-7 forward again over columns 4-5, with
 * the chart's orientation: the chart covers centres twice with one orientation at the start,
 * which no scaffold can box. */
static texopt_mesh *z_folded_strip(void)
{
    cell cells[16];
    size_t n = 0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 8; i++)
            cells[n++] = (cell){i, j, 0};
    texopt_mesh *m = cell_mesh(cells, n, 1, 8);
    for (size_t v = 0; v < m->vertex_count; v++) {
        double i = m->position[3 * v];
        if (i >= 6)
            m->texel[2 * v] = CELL * (i - 2); /* 6 -> 4, 7 -> 5, 8 -> 6 */
    }
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    return m;
}

/* closing_u and its mirror image welded along the right arm's outer edge (lattice x = 5):
 * the mirrored U lies on the first with the other orientation, as mirrored halves do in
 * the sample assets (neither half FLIPPED). Both halves' arms ask to be 2.5 times wider. */
static texopt_mesh *mirrored_u(texopt_triangle_target **targets)
{
    cell cells[128];
    size_t n = 0;
    for (int j = 0; j < 7; j++)
        for (int i = 0; i < 10; i++)
            if (j == 0 || (i != 2 && i != 7))
                cells[n++] = (cell){i, j, 0};
    texopt_mesh *m = cell_mesh(cells, n, 1, 10);
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->position[3 * v] > 5)
            m->texel[2 * v] = CELL * (10 - m->position[3 * v]);
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    for (size_t t = 0; t < m->triangle_count; t++)   /* handmesh marks every clockwise triangle */
        m->flags[t] &= (uint8_t)~TEXOPT_TRI_FLIPPED; /* mesh.h: a mirror's halves are not FLIPPED */
    *targets = malloc(m->triangle_count * sizeof **targets);
    for (size_t c = 0; c < n; c++)
        (*targets)[2 * c] = (*targets)[2 * c + 1] = stretch_target(cells[c].j > 0 ? 2.5 : 1.0, 1.0);
    return m;
}

TEST(each_half_of_a_mirror_is_kept_off_itself)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = mirrored_u(&tg);
    double *plain = malloc(2 * m->vertex_count * sizeof *plain), *bij = malloc(2 * m->vertex_count * sizeof *bij);
    char err[256];
    size_t within, between, overlapping = 99;
    uint8_t over = 1;
    CHECK_OK(texopt_scaffold_overlapping_charts(m, m->texel, &over, &overlapping, err, sizeof err), err);
    CHECK_EQ_INT(overlapping, 0);
    CHECK_OK(texopt_meshwise_solve(m, tg, NULL, NULL, plain, NULL, NULL, err, sizeof err), err);
    CHECK_OK(texopt_count_overlap(m, plain, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "without scaffold: %zu texels covered twice with one orientation", within);
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, NULL, bij, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_scaffolded, 1);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK_OK(texopt_count_overlap(m, bij, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(texopt_count_flipped(m, bij), 0);
    free(plain);
    free(bij);
    free(tg);
    texopt_mesh_destroy(m);
}

/* The vertex of m at lattice point (i, j). */
static uint32_t lattice_vertex(const texopt_mesh *m, double i, double j)
{
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->position[3 * v] == i && m->position[3 * v + 1] == j)
            return (uint32_t)v;
    return UINT32_MAX;
}

/* mirrored_u with its halves also joined, as DamagedHelmet's clean mirrors are, by a quad
 * collapsed in the layout: two triangles between the left half's outer edge (lattice x = 0)
 * and the right half's (x = 10), which lie on one another, so each triangle has two corners
 * on one point and no area. */
static texopt_mesh *bridged_mirror(texopt_triangle_target **targets)
{
    texopt_triangle_target *tg;
    texopt_mesh *u = mirrored_u(&tg);
    uint32_t l0 = lattice_vertex(u, 0, 0), l1 = lattice_vertex(u, 0, 1);
    uint32_t r0 = lattice_vertex(u, 10, 0), r1 = lattice_vertex(u, 10, 1);
    size_t nt = u->triangle_count;
    texopt_mesh *m = handmesh_alloc(u->vertex_count, nt + 2);
    memcpy(m->texel, u->texel, 2 * u->vertex_count * sizeof *m->texel);
    memcpy(m->position, u->position, 3 * u->vertex_count * sizeof *m->position);
    memcpy(m->triangle, u->triangle, 3 * nt * sizeof *m->triangle);
    uint32_t bridge[6] = {l0, r0, r1, r1, l1, l0};
    memcpy(m->triangle + 3 * nt, bridge, sizeof bridge);
    m->width = u->width;
    m->height = u->height;
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    for (size_t t = 0; t < m->triangle_count; t++)
        m->flags[t] &= (uint8_t)~TEXOPT_TRI_FLIPPED;
    *targets = malloc(m->triangle_count * sizeof **targets);
    memcpy(*targets, tg, nt * sizeof *tg);
    (*targets)[nt] = (*targets)[nt + 1] = stretch_target(1.0, 1.0);
    free(tg);
    texopt_mesh_destroy(u);
    return m;
}

TEST(a_mirror_joined_by_triangles_without_area_is_boxed_half_by_half)
{
    texopt_triangle_target *tg;
    texopt_mesh *m = bridged_mirror(&tg);
    CHECK(m->area_texel[m->triangle_count - 1] == 0.0 && m->area_texel[m->triangle_count - 2] == 0.0);
    double *bij = malloc(2 * m->vertex_count * sizeof *bij);
    char err[256];
    size_t within, between, overlapping = 99;
    uint8_t over = 1;
    CHECK_OK(texopt_scaffold_overlapping_charts(m, m->texel, &over, &overlapping, err, sizeof err), err);
    CHECK_EQ_INT(overlapping, 0);
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, NULL, bij, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_scaffolded, 1);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK_OK(texopt_count_overlap(m, bij, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(texopt_count_flipped(m, bij), 0);
    free(bij);
    free(tg);
    texopt_mesh_destroy(m);
}

/* Triangles of m that are not counter-clockwise in the layout texel. */
static size_t clockwise(const texopt_mesh *m, const double *texel)
{
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        n += !(handmesh_doubled_area(texel, m->triangle + 3 * t, 2) > 0);
    return n;
}

/* A copy of m (its own arrays) with the layout texel. */
static texopt_mesh *with_layout(const texopt_mesh *m, const double *texel)
{
    texopt_mesh *c = handmesh_alloc(m->vertex_count, m->triangle_count);
    memcpy(c->texel, texel, 2 * m->vertex_count * sizeof *texel);
    memcpy(c->position, m->position, 3 * m->vertex_count * sizeof *c->position);
    memcpy(c->triangle, m->triangle, 3 * m->triangle_count * sizeof *c->triangle);
    memcpy(c->chart_of, m->chart_of, m->triangle_count * sizeof *c->chart_of);
    c->chart_count = m->chart_count;
    c->width = m->width;
    c->height = m->height;
    c->chart_sign = malloc(m->chart_count);
    memcpy(c->chart_sign, m->chart_sign, m->chart_count);
    handmesh_finish(c);
    return c;
}

TEST(a_folded_chart_is_unfolded_so_the_scaffold_leaves_no_centre_twice)
{
    texopt_mesh *m = z_folded_strip();
    size_t nv = m->vertex_count, within, between, count;
    char err[256];
    CHECK_OK(texopt_count_overlap(m, m->texel, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "the fold covers %zu centres twice", within);
    texopt_triangle_target *tg = malloc(m->triangle_count * sizeof *tg);
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t] = stretch_target(1.3, 1.0); /* a little longer, as a layout method would ask */
    double *out = malloc(2 * nv * sizeof *out);
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 1);
    CHECK_OK(texopt_count_overlap(m, out, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "solved from the fold: %zu centres twice", within);

    double *unfolded = malloc(2 * nv * sizeof *unfolded);
    uint8_t laid = 0;
    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_charts(m, NULL, unfolded, &laid, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.overlapping, 1);
    CHECK_EQ_INT(ur.unfolded, 1);
    CHECK_EQ_INT(ur.tutte, 0); /* flat in 3D: ABF lays it out without flips */
    CHECK_EQ_INT(laid, 1);
    /* Flat in 3D, so the layout is the 3D strip scaled to the input's texel area (16 cells
     * of CELL^2): every edge CELL times its 3D length. */
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->triangle[3 * t + (size_t)k], b = m->triangle[3 * t + (size_t)(k + 1) % 3];
            double d3 = hypot(m->position[3 * a] - m->position[3 * b], m->position[3 * a + 1] - m->position[3 * b + 1]);
            double d2 = hypot(unfolded[2 * a] - unfolded[2 * b], unfolded[2 * a + 1] - unfolded[2 * b + 1]);
            CHECK_NEAR(d2, CELL * d3, 1e-6);
        }
    texopt_mesh *layout = with_layout(m, unfolded);
    CHECK_EQ_INT(clockwise(layout, layout->texel), 0);
    uint8_t over;
    CHECK_OK(texopt_scaffold_overlapping_charts(layout, layout->texel, &over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);

    texopt_targets_restate(m, layout, tg);
    CHECK_OK(texopt_scaffold_solve(layout, tg, NULL, NULL, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK_EQ_INT(rep.charts_scaffolded, 1);
    CHECK_OK(texopt_count_overlap(layout, out, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(clockwise(layout, out), 0);
    free(out);
    free(unfolded);
    free(tg);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}

/* One chart of 3 x 3 cells less the centre: a ring round a hole of one cell. */
static texopt_mesh *ring_of_cells(void)
{
    cell cells[8];
    size_t n = 0;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++)
            if (i != 1 || j != 1)
                cells[n++] = (cell){i, j, 0};
    return cell_mesh(cells, n, 1, 3);
}

TEST(a_chart_with_a_hole_and_a_fold_is_unfolded_by_tutte)
{
    /* 3 x 3 cells less the centre (a hole), its top right corner cell folded over its
     * neighbours: both boundary loops are kept, the hole filled only for the layout. */
    texopt_mesh *m = ring_of_cells();
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->position[3 * v] == 3 && m->position[3 * v + 1] == 3)
            m->texel[2 * v] = m->texel[2 * v + 1] = 1.5 * CELL;
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    char err[256];
    CHECK(clockwise(m, m->texel) > 0);
    double *unfolded = malloc(2 * m->vertex_count * sizeof *unfolded);
    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_charts(m, NULL, unfolded, NULL, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.overlapping, 1);
    CHECK_EQ_INT(ur.unfolded, 1);
    CHECK_EQ_INT(ur.tutte, 1);
    texopt_mesh *layout = with_layout(m, unfolded);
    CHECK_EQ_INT(clockwise(layout, layout->texel), 0);
    size_t count;
    uint8_t over;
    CHECK_OK(texopt_scaffold_overlapping_charts(layout, layout->texel, &over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);
    /* the kept chart's texel area */
    double before = 0, after = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        before += fabs(m->area_texel[t]);
        after += fabs(layout->area_texel[t]);
    }
    CHECK_NEAR(after, before, 1e-9 * before);
    uint8_t keep = 1;
    CHECK_OK(texopt_unfold_charts(m, &keep, unfolded, NULL, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.kept, 1);
    CHECK_EQ_INT(ur.unfolded, 0);
    CHECK(memcmp(unfolded, m->texel, 2 * m->vertex_count * sizeof *unfolded) == 0);
    free(unfolded);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}

/* A U as closing_u's, twice, as two charts on the same texels (repeated twins of a sharing
 * group, texel_share.h), its right arm drawn 1.5 cells to the left from lattice row 2 up:
 * it lies half a cell over the left arm (no fold, one orientation), its vertices inside the
 * left arm's cells, so each chart covers centres twice at the start. The second chart's arm
 * is drawn shift_second cells instead (1.5: twins). */
static texopt_mesh *overlapping_twins(double shift_second)
{
    cell cells[128];
    size_t n = 0;
    for (uint32_t c = 0; c < 2; c++)
        for (int j = 0; j < 7; j++)
            for (int i = 0; i < 5; i++)
                if (j == 0 || i != 2)
                    cells[n++] = (cell){i, j, c};
    texopt_mesh *m = cell_mesh(cells, n, 2, 8);
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->position[3 * v] >= 3 && m->position[3 * v + 1] >= 2)
            m->texel[2 * v] -= (v < m->vertex_count / 2 ? 1.5 : shift_second) * CELL;
    m->chart_sign = malloc(2);
    m->chart_sign[0] = m->chart_sign[1] = 1;
    handmesh_finish(m);
    return m;
}

TEST(twins_of_a_sharing_group_are_unfolded_as_one_and_stay_off_themselves)
{
    texopt_mesh *m = overlapping_twins(1.5);
    size_t nv = m->vertex_count, within, between;
    char err[256];
    texopt_texel_share *share = NULL;
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    CHECK_EQ_INT(share->secondary_count, 1);
    texopt_triangle_target *tg = malloc(m->triangle_count * sizeof *tg);
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t] = stretch_target(1.3, 1.0);
    double *out = malloc(2 * nv * sizeof *out), *start = malloc(2 * nv * sizeof *start);
    texopt_meshwise_options mo = {.share = share};
    texopt_scaffold_report rep;
    /* the twins left as they are: both skipped, both over themselves */
    CHECK_OK(texopt_scaffold_solve(m, tg, NULL, &mo, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 2);
    CHECK_OK(texopt_count_overlap(m, out, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "solved from the folds: %zu centres twice", within);

    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_groups(m, share, start, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.overlapping, 2);
    CHECK_EQ_INT(ur.unfolded, 1);
    CHECK_EQ_INT(ur.followed, 1);
    CHECK_EQ_INT(ur.kept, 0);
    /* the secondary starts on the primary's new layout: its twin vertices at the same point */
    size_t twins = 0;
    for (size_t a = 0; a < nv; a++)
        for (size_t b = 0; b < nv; b++)
            if (m->position[3 * a] == m->position[3 * b] && m->position[3 * a + 1] == m->position[3 * b + 1] &&
                a != b) {
                CHECK_NEAR(start[2 * a], start[2 * b], 1e-9);
                CHECK_NEAR(start[2 * a + 1], start[2 * b + 1], 1e-9);
                twins++;
            }
    CHECK_EQ_INT(twins, nv);
    texopt_mesh *layout = with_layout(m, start);
    texopt_texel_share_rebase(share, layout);
    texopt_targets_restate(m, layout, tg);
    CHECK_OK(texopt_scaffold_solve(layout, tg, NULL, &mo, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK_EQ_INT(rep.charts_scaffolded, 2);
    CHECK_OK(texopt_count_overlap(layout, out, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(clockwise(layout, out), 0);
    /* and the twins still share their texels: every secondary vertex on its primary twin */
    double apart = 0;
    for (size_t a = 0; a < nv; a++)
        for (size_t b = 0; b < nv; b++)
            if (m->position[3 * a] == m->position[3 * b] && m->position[3 * a + 1] == m->position[3 * b + 1] && a != b)
                apart = fmax(apart, hypot(out[2 * a] - out[2 * b], out[2 * a + 1] - out[2 * b + 1]));
    CHECK_MSG(apart < 0.1, "twins %g texels apart", apart);
    free(out);
    free(start);
    free(tg);
    texopt_texel_share_destroy(share);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}

TEST(a_chart_of_parts_meeting_at_a_corner_is_unfolded_part_by_part)
{
    /* Two cells of one chart joined only at lattice point (1, 1), the second turned a half
     * turn about it in the input layout, so it lies on the first with the same orientation. */
    cell cells[] = {{0, 0, 0}, {1, 1, 0}};
    texopt_mesh *m = cell_mesh(cells, 2, 1, 2);
    for (size_t v = 0; v < m->vertex_count; v++)
        if (m->position[3 * v] + m->position[3 * v + 1] > 2) { /* the second cell's own corners */
            m->texel[2 * v] = 2 * CELL - m->texel[2 * v];
            m->texel[2 * v + 1] = 2 * CELL - m->texel[2 * v + 1];
        }
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    char err[256];
    size_t within, between, count;
    CHECK_OK(texopt_count_overlap(m, m->texel, &within, &between, err, sizeof err), err);
    CHECK_MSG(within > 10, "the second cell covers %zu centres of the first", within);
    double *unfolded = malloc(2 * m->vertex_count * sizeof *unfolded);
    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_charts(m, NULL, unfolded, NULL, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.overlapping, 1);
    CHECK_EQ_INT(ur.unfolded, 1);
    CHECK_EQ_INT(ur.not_disks, 0);
    texopt_mesh *layout = with_layout(m, unfolded);
    uint8_t over;
    CHECK_OK(texopt_scaffold_overlapping_charts(layout, layout->texel, &over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);
    CHECK_EQ_INT(clockwise(layout, layout->texel), 0);
    /* each cell keeps its square (flat in 3D): every edge CELL times its 3D length */
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->triangle[3 * t + (size_t)k], b = m->triangle[3 * t + (size_t)(k + 1) % 3];
            double d3 = hypot(m->position[3 * a] - m->position[3 * b], m->position[3 * a + 1] - m->position[3 * b + 1]);
            double d2 = hypot(unfolded[2 * a] - unfolded[2 * b], unfolded[2 * a + 1] - unfolded[2 * b + 1]);
            CHECK_NEAR(d2, CELL * d3, 1e-6);
        }
    free(unfolded);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}

TEST(a_secondary_over_itself_that_is_no_twin_leaves_its_group)
{
    /* the second U's arm 1.25 cells to the left: it lies on the first's texels but not as its
     * twin, and covers some of them twice on its own */
    texopt_mesh *m = overlapping_twins(1.25);
    size_t nv = m->vertex_count, within, between;
    char err[256];
    texopt_texel_share *share = NULL;
    CHECK_OK(texopt_texel_share_create(&share, m, err, sizeof err), err);
    CHECK_EQ_INT(share->secondary_count, 1);
    double *start = malloc(2 * nv * sizeof *start), *out = malloc(2 * nv * sizeof *out);
    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_groups(m, share, start, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.overlapping, 2);
    CHECK_EQ_INT(ur.unfolded, 2);
    CHECK_EQ_INT(ur.followed, 0);
    CHECK_EQ_INT(share->secondary_count, 0);
    CHECK_EQ_INT(share->tie_count, 0);
    CHECK_EQ_INT(share->view.chart_count, 2);
    texopt_mesh *layout = with_layout(m, start);
    uint8_t over[2];
    size_t count;
    CHECK_OK(texopt_scaffold_overlapping_charts(layout, layout->texel, over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);
    texopt_texel_share_rebase(share, layout);
    texopt_triangle_target *tg = malloc(m->triangle_count * sizeof *tg);
    for (size_t t = 0; t < m->triangle_count; t++)
        tg[t] = stretch_target(1.3, 1.0);
    texopt_targets_restate(m, layout, tg);
    texopt_meshwise_options mo = {.share = share};
    texopt_scaffold_report rep;
    CHECK_OK(texopt_scaffold_solve(layout, tg, NULL, &mo, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_skipped, 0);
    CHECK_OK(texopt_count_overlap(layout, out, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    free(start);
    free(out);
    free(tg);
    texopt_texel_share_destroy(share);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}

/* A ring of 3 x 3 cells less the centre, and a strip 3 cells long and 0.2 wide hanging at
 * the hole's lower left corner, lattice (1, 1), its only vertex in common with the ring
 * (one chart of two parts); in the input layout the strip lies over the ring's cells right
 * of the hole. */
static texopt_mesh *ring_with_strip(void)
{
    texopt_mesh *ring = ring_of_cells();
    size_t nv = ring->vertex_count, nt = ring->triangle_count;
    texopt_mesh *m = handmesh_alloc(nv + 3, nt + 2);
    memcpy(m->texel, ring->texel, 2 * nv * sizeof *m->texel);
    memcpy(m->position, ring->position, 3 * nv * sizeof *m->position);
    memcpy(m->triangle, ring->triangle, 3 * nt * sizeof *m->triangle);
    uint32_t p = lattice_vertex(ring, 1, 1), b = (uint32_t)nv;
    double pos[9] = {1, 1, 3, 1, 1.2, 3, 1, 1.2, 0};
    double tex[6] = {CELL + 3 * CELL, CELL, CELL + 3 * CELL, CELL + 0.2 * CELL, CELL, CELL + 0.2 * CELL};
    memcpy(m->position + 3 * nv, pos, sizeof pos);
    memcpy(m->texel + 2 * nv, tex, sizeof tex);
    uint32_t strip[6] = {p, b, b + 1, p, b + 1, b + 2};
    memcpy(m->triangle + 3 * nt, strip, sizeof strip);
    m->width = ring->width;
    m->height = ring->height;
    m->chart_sign = malloc(1);
    m->chart_sign[0] = 1;
    handmesh_finish(m);
    texopt_mesh_destroy(ring);
    return m;
}

TEST(a_part_that_clashes_at_every_turn_is_shrunk_until_it_fits)
{
    /* Turned about its corner, the strip (12 texels) meets the ring at every angle: the hole
     * is 4 texels wide. A quarter of its length fits the hole along its diagonal. */
    texopt_mesh *m = ring_with_strip();
    char err[256];
    size_t count;
    uint8_t over;
    CHECK_OK(texopt_scaffold_overlapping_charts(m, m->texel, &over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 1);
    double *unfolded = malloc(2 * m->vertex_count * sizeof *unfolded);
    texopt_unfold_report ur;
    CHECK_OK(texopt_unfold_charts(m, NULL, unfolded, NULL, &ur, err, sizeof err), err);
    CHECK_EQ_INT(ur.unfolded, 1);
    texopt_mesh *layout = with_layout(m, unfolded);
    CHECK_OK(texopt_scaffold_overlapping_charts(layout, layout->texel, &over, &count, err, sizeof err), err);
    CHECK_EQ_INT(count, 0);
    CHECK_EQ_INT(clockwise(layout, layout->texel), 0);
    size_t nt = m->triangle_count;
    double strip = fabs(layout->area_texel[nt - 1]) + fabs(layout->area_texel[nt - 2]);
    double input = fabs(m->area_texel[nt - 1]) + fabs(m->area_texel[nt - 2]);
    CHECK_MSG(strip <= input / 16 * (1 + 1e-9), "the strip keeps %g of its input area", strip / input);
    free(unfolded);
    texopt_mesh_destroy(layout);
    texopt_mesh_destroy(m);
}
