/* test_chart_cut.c - axis-aligned charts cut into pieces along mesh edges
 * (engine/layout/chart_cut.c, texopt_atlas_cut in engine/layout/atlas_refine.c).
 *
 * Planar grid charts of 12 x 12 cells of 8 texels, interior vertices jittered, boundary
 * exactly axis-aligned: an L (one quadrant removed) and a U (a notch 4 cells wide, 6 deep).
 * The L's one reflex corner gives one cut of 6 grid edges: pieces of 144 and 72 triangles,
 * 7 vertices split. The U's two reflex corners give two cuts of 4 edges cutting its arms
 * off: pieces of 144, 48 and 48 triangles, 10 vertices split. For both: every triangle in
 * exactly one piece, the cut mesh's triangles where they were, the packed pieces (pack.h)
 * more efficient than the packed chart and passing the layout check without overlap. A
 * chart turned by 30 degrees is not axis-aligned and stays whole. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_refine.h"
#include "chart_cut.h"
#include "handmesh.h"
#include "layout_check.h"
#include "pack.h"
#include "rng.h"
#include "test.h"

#define N 12
#define CELL 8.0

typedef int (*shape_fn)(int i, int j);

static int l_shape(int i, int j)
{
    return !(i >= N / 2 && j >= N / 2);
}

static int u_shape(int i, int j)
{
    return !(i >= 4 && i < 8 && j >= 6);
}

static int vertex_used(shape_fn in, int i, int j)
{
    int used = 0;
    for (int di = -1; di <= 0; di++)
        for (int dj = -1; dj <= 0; dj++) {
            int ci = i + di, cj = j + dj;
            used |= ci >= 0 && cj >= 0 && ci < N && cj < N && in(ci, cj);
        }
    return used;
}

/* Whether grid vertex (i, j) touches a cell outside the shape or the grid's edge. */
static int on_outline(shape_fn in, int i, int j)
{
    for (int di = -1; di <= 0; di++)
        for (int dj = -1; dj <= 0; dj++) {
            int ci = i + di, cj = j + dj;
            if (ci < 0 || cj < 0 || ci >= N || cj >= N || !in(ci, cj))
                return 1;
        }
    return 0;
}

/* One chart of the shape, turned by `turn` radians. */
static texopt_mesh *grid_chart(shape_fn in, double turn)
{
    size_t cells = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            cells += (size_t)in(i, j);
    texopt_mesh *m = handmesh_alloc((N + 1) * (N + 1), 2 * cells);
    if (!m)
        return NULL;
    m->chart_count = 1;
    texopt_rng rng;
    texopt_rng_seed(&rng, 11);
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double jitter = vertex_used(in, i, j) && !on_outline(in, i, j) ? 0.15 : 0.0;
            double x = CELL * (i + jitter * (texopt_rng_uniform(&rng) - 0.5));
            double y = CELL * (j + jitter * (texopt_rng_uniform(&rng) - 0.5));
            double *p = m->texel + 2 * (size_t)(j * (N + 1) + i), *q = m->position + 3 * (size_t)(j * (N + 1) + i);
            p[0] = q[0] = cos(turn) * x - sin(turn) * y;
            p[1] = q[1] = sin(turn) * x + cos(turn) * y;
        }
    size_t t = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            if (!in(i, j))
                continue;
            uint32_t a = (uint32_t)(j * (N + 1) + i), tri[6] = {a, a + 1, a + N + 2, a, a + N + 2, a + N + 1};
            memcpy(m->triangle + 3 * t, tri, sizeof tri);
            t += 2;
        }
    handmesh_finish(m);
    m->model_triangle = malloc(m->triangle_count * sizeof *m->model_triangle); /* the layout check names them */
    for (size_t k = 0; m->model_triangle && k < m->triangle_count; k++)
        m->model_triangle[k] = (uint32_t)k;
    return m;
}

/* Packs mesh's charts (laid out at texel) into a strip 200 texels wide; returns the packing
 * efficiency, the placed layout in placed. */
static double packed_efficiency(const texopt_mesh *m, const double *texel, double *placed)
{
    texopt_pack_result r;
    int fits = 0;
    char err[256];
    if (texopt_pack_charts(m, texel, 200, 0, NULL, placed, &r, &fits, err, sizeof err) != TEXOPT_OK || !fits)
        return 0;
    double pe = r.area_efficiency;
    texopt_pack_result_destroy(&r);
    return pe;
}

typedef struct cut_outcome {
    size_t pieces, cuts, added, smallest, largest;
    double pe_before, pe_after;
    size_t overlapping;
} cut_outcome;

static void cut_and_pack(shape_fn in, cut_outcome *o)
{
    memset(o, 0, sizeof *o);
    texopt_mesh *m = grid_chart(in, 0);
    CHECK(m != NULL);
    uint32_t *piece = malloc(m->triangle_count * sizeof *piece), *source = NULL;
    size_t pieces = 0;
    char err[256];
    texopt_atlas_refine_report rep = {0};
    CHECK_OK(texopt_atlas_cut(m, m->texel, NULL, NULL, piece, &pieces, &rep, NULL, err, sizeof err), err);
    o->pieces = pieces;
    o->cuts = rep.cuts;
    texopt_mesh *cut = NULL;
    CHECK_OK(texopt_mesh_cut_create(m, piece, pieces, &cut, &source, err, sizeof err), err);
    o->added = cut->vertex_count - m->vertex_count;
    /* every triangle once, in its piece, where it was */
    CHECK(cut->triangle_count == m->triangle_count && cut->chart_count == pieces);
    size_t *count = calloc(pieces, sizeof *count);
    for (size_t t = 0; t < m->triangle_count; t++) {
        CHECK(piece[t] < pieces && cut->chart_of[t] == piece[t]);
        count[piece[t]]++;
        for (int k = 0; k < 3; k++) {
            uint32_t v = cut->triangle[3 * t + k];
            CHECK(source[v] == m->triangle[3 * t + k]);
            CHECK(cut->texel[2 * v] == m->texel[2 * source[v]] && cut->texel[2 * v + 1] == m->texel[2 * source[v] + 1]);
        }
    }
    o->smallest = SIZE_MAX;
    for (size_t p = 0; p < pieces; p++) {
        o->smallest = count[p] < o->smallest ? count[p] : o->smallest;
        o->largest = count[p] > o->largest ? count[p] : o->largest;
    }
    /* a vertex is shared by two pieces only through its copy: pieces share no vertex */
    uint32_t *owner = malloc(cut->vertex_count * sizeof *owner);
    memset(owner, 0xff, cut->vertex_count * sizeof *owner);
    for (size_t t = 0; t < cut->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = cut->triangle[3 * t + k];
            CHECK(owner[v] == UINT32_MAX || owner[v] == piece[t]);
            owner[v] = piece[t];
        }
    double *placed = malloc(2 * cut->vertex_count * sizeof *placed);
    o->pe_before = packed_efficiency(m, m->texel, placed);
    o->pe_after = packed_efficiency(cut, cut->texel, placed);
    texopt_layout_check check;
    CHECK_OK(texopt_layout_check_run(cut, placed, 200, 200, NULL, NULL, &check, err, sizeof err), err);
    o->overlapping = check.overlapping;
    free(placed);
    free(owner);
    free(count);
    free(piece);
    free(source);
    texopt_mesh_destroy(cut);
    texopt_mesh_destroy(m);
}

TEST(an_l_is_cut_once_into_two_rectangles)
{
    cut_outcome o;
    cut_and_pack(l_shape, &o);
    CHECK_EQ_INT(o.pieces, 2);
    CHECK_EQ_INT(o.cuts, 1);
    CHECK_EQ_INT(o.smallest, 72);
    CHECK_EQ_INT(o.largest, 144);
    CHECK_EQ_INT(o.added, 7);
    CHECK_EQ_INT(o.overlapping, 0);
    CHECK_MSG(o.pe_after > o.pe_before + 0.1, "packing efficiency %.3f -> %.3f", o.pe_before, o.pe_after);
}

TEST(a_u_is_cut_twice_into_three_rectangles)
{
    cut_outcome o;
    cut_and_pack(u_shape, &o);
    CHECK_EQ_INT(o.pieces, 3);
    CHECK_EQ_INT(o.cuts, 2);
    /* eq. 11 prefers the arms cut off (12 x 6 and twice 4 x 6 cells: less boundary, packed
     * in a row) to three columns: two cuts of 4 grid edges, 5 vertices each */
    CHECK_EQ_INT(o.smallest, 48);
    CHECK_EQ_INT(o.largest, 144);
    CHECK_EQ_INT(o.added, 10);
    CHECK_EQ_INT(o.overlapping, 0);
    CHECK_MSG(o.pe_after > o.pe_before + 0.1, "packing efficiency %.3f -> %.3f", o.pe_before, o.pe_after);
}

TEST(a_turned_chart_stays_whole)
{
    texopt_mesh *m = grid_chart(l_shape, 30.0 * 3.14159265358979323846 / 180.0);
    CHECK(m != NULL);
    uint32_t *piece = malloc(m->triangle_count * sizeof *piece);
    size_t pieces = 0;
    texopt_atlas_refine_report rep = {0};
    CHECK(texopt_atlas_cut(m, m->texel, NULL, NULL, piece, &pieces, &rep, NULL, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(pieces, 1);
    CHECK_EQ_INT(rep.charts_cut, 0);
    free(piece);
    texopt_mesh_destroy(m);
}

TEST(a_chart_in_keep_shape_stays_whole)
{
    texopt_mesh *m = grid_chart(u_shape, 0);
    CHECK(m != NULL);
    uint32_t *piece = malloc(m->triangle_count * sizeof *piece);
    size_t pieces = 0;
    uint8_t keep = 1;
    CHECK(texopt_atlas_cut(m, m->texel, &keep, NULL, piece, &pieces, NULL, NULL, NULL, 0) == TEXOPT_OK);
    CHECK_EQ_INT(pieces, 1);
    free(piece);
    texopt_mesh_destroy(m);
}

/* Runs that do not alternate between the axes (two edges of one direction with an edge of
 * the opposite one between) are refused. */
TEST(a_boundary_without_alternating_runs_is_refused)
{
    double xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
    uint32_t tri[] = {0, 1, 2, 0, 2, 3}, loop[] = {0, 1, 2, 3};
    int theta[] = {0, 0, 2, 2};
    texopt_chart_cut cut;
    char err[256];
    CHECK(texopt_chart_cut_compute(4, xy, 2, tri, loop, theta, 4, NULL, &cut, err, sizeof err) ==
          TEXOPT_E_INVALID_ARGUMENT);
}
