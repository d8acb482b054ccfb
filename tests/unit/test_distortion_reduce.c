/* test_distortion_reduce.c - a packed atlas's charts pulled back toward their reference
 * shapes in a fixed box (engine/layout/distortion_reduce.c, Liu et al. 2019 Algorithm 2).
 *
 * An L chart of 12 x 12 cells, one quadrant removed: its input texels a jittered grid of
 * 4-texel cells, its reference layout (stage 2's, in the job) a grid of 8-texel cells
 * sheared by a quarter, turned by 20 degrees and jittered anew. The refinement bends it axis-aligned (atlas_refine.h), the cut splits it in
 * two rectangles (chart_cut.h), the packer places them (pack.h). Reduced from there: the
 * distortion relative to the reference falls by more than half of its excess over 1, no
 * triangle reverses, no texel centre is covered twice, every vertex lies in the last box,
 * whose size is the start's bounding box scaled by the initial scale, delta and the
 * growth of its rounds, so the packing efficiency is at least the chart area over it. A
 * packing bound above any reachable ends the reduction before its first round; pieces laid
 * over each other are refused and returned as they came; a folded chart is left out of the
 * box while the others are reduced. Two squares side by side, the right one's reference
 * 2 times its size: growing in the box it presses against the left one until they touch,
 * unless both carry a gap layer (gap_layer.h) of 3/4 of the gap, which keeps them at least
 * the gap apart. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "atlas_refine.h"
#include "chart_cut.h"
#include "chart_gap.h"
#include "distortion_reduce.h"
#include "handmesh.h"
#include "pack.h"
#include "rng.h"
#include "scaffold.h"
#include "test.h"

#define N 12
#define CELL 8.0
#define TURN (20.0 * 3.14159265358979323846 / 180.0)
#define SHEAR 0.25

static int in_l(int i, int j)
{
    return !(i >= N / 2 && j >= N / 2);
}

/* The L as one chart; only the grid vertices its cells use. Its input texels are the grid
 * at half a cell, jittered; the reference (2 per vertex, caller frees) is the grid at CELL,
 * sheared, turned and jittered anew, so the reference Jacobians vary from triangle to
 * triangle. */
static texopt_mesh *l_chart(double **reference)
{
    int id[(N + 1) * (N + 1)];
    size_t nv = 0, nt = 0;
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            int used = 0;
            for (int dj = -1; dj <= 0; dj++)
                for (int di = -1; di <= 0; di++)
                    used |= i + di >= 0 && j + dj >= 0 && i + di < N && j + dj < N && in_l(i + di, j + dj);
            id[j * (N + 1) + i] = used ? (int)nv++ : -1;
        }
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            nt += 2 * (size_t)in_l(i, j);
    texopt_mesh *m = handmesh_alloc(nv, nt);
    *reference = malloc(2 * nv * sizeof **reference);
    if (!m || !*reference)
        return NULL;
    m->width = m->height = 256;
    texopt_rng rng;
    texopt_rng_seed(&rng, 11);
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            int k = id[j * (N + 1) + i];
            if (k < 0)
                continue;
            m->texel[2 * k] = 0.5 * CELL * (i + 0.2 * (texopt_rng_uniform(&rng) - 0.5));
            m->texel[2 * k + 1] = 0.5 * CELL * (j + 0.2 * (texopt_rng_uniform(&rng) - 0.5));
            m->position[3 * k] = m->texel[2 * k];
            m->position[3 * k + 1] = m->texel[2 * k + 1];
            double y = CELL * (j + 0.2 * (texopt_rng_uniform(&rng) - 0.5));
            double x = CELL * (i + 0.2 * (texopt_rng_uniform(&rng) - 0.5)) + SHEAR * y;
            (*reference)[2 * k] = 128 + cos(TURN) * x - sin(TURN) * y;
            (*reference)[2 * k + 1] = 20 + sin(TURN) * x + cos(TURN) * y;
        }
    size_t t = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            if (!in_l(i, j))
                continue;
            uint32_t a = (uint32_t)id[j * (N + 1) + i], b = (uint32_t)id[j * (N + 1) + i + 1];
            uint32_t d = (uint32_t)id[(j + 1) * (N + 1) + i], e = (uint32_t)id[(j + 1) * (N + 1) + i + 1];
            uint32_t tri[6] = {a, b, e, a, e, d};
            memcpy(m->triangle + 3 * t, tri, sizeof tri);
            t += 2;
        }
    handmesh_finish(m);
    return m;
}

/* The L's reference refined, cut and packed: the cut mesh (NULL on a failed check), the
 * reference and the packed start on it (caller frees all three). */
static void packed_pieces(texopt_mesh **out, double **reference, double **start)
{
    char err[256];
    double *whole = NULL;
    texopt_mesh *m = l_chart(&whole), *cut = NULL;
    *out = NULL;
    CHECK(m != NULL);
    double *refined = malloc(2 * m->vertex_count * sizeof *refined);
    uint32_t *piece = malloc(m->triangle_count * sizeof *piece), *source = NULL;
    texopt_atlas_refine_report rr;
    CHECK_OK(texopt_atlas_refine(m, whole, NULL, NULL, 0, refined, &rr, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rr.charts_refined, 1);
    size_t pieces = 0;
    CHECK_OK(texopt_atlas_cut(m, refined, NULL, NULL, piece, &pieces, &rr, NULL, err, sizeof err), err);
    CHECK_EQ_INT(pieces, 2);
    CHECK_OK(texopt_mesh_cut_create(m, piece, pieces, &cut, &source, err, sizeof err), err);
    double *on_cut = malloc(2 * cut->vertex_count * sizeof *on_cut);
    *reference = malloc(2 * cut->vertex_count * sizeof **reference);
    *start = malloc(2 * cut->vertex_count * sizeof **start);
    for (size_t v = 0; v < cut->vertex_count; v++) {
        memcpy(on_cut + 2 * v, refined + 2 * (size_t)source[v], 2 * sizeof *on_cut);
        memcpy(*reference + 2 * v, whole + 2 * (size_t)source[v], 2 * sizeof *on_cut);
    }
    texopt_pack_result pr;
    int fits = 0;
    CHECK_OK(texopt_pack_charts(cut, on_cut, 160, 0, NULL, *start, &pr, &fits, err, sizeof err), err);
    CHECK(fits);
    texopt_pack_result_destroy(&pr);
    free(on_cut);
    free(refined);
    free(piece);
    free(source);
    free(whole);
    texopt_mesh_destroy(m);
    *out = cut;
}

static double layout_area(const texopt_mesh *m, const double *x, size_t *reversed)
{
    double area = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        double a = 0.5 * handmesh_doubled_area(x, m->triangle + 3 * t, 2);
        *reversed += !(a > 0) != !(m->area_texel[t] > 0);
        area += fabs(a);
    }
    return area;
}

static void bounding_box(const texopt_mesh *m, const double *x, double box[4])
{
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    for (size_t k = 0; k < 3 * m->triangle_count; k++)
        for (int a = 0; a < 2; a++) {
            box[a] = fmin(box[a], x[2 * (size_t)m->triangle[k] + a]);
            box[a + 2] = fmax(box[a + 2], x[2 * (size_t)m->triangle[k] + a]);
        }
}

TEST(a_cut_l_returns_toward_its_shape_inside_the_box)
{
    double *start = NULL;
    double *reference = NULL;
    texopt_mesh *cut = NULL;
    packed_pieces(&cut, &reference, &start);
    CHECK(cut != NULL);
    double *out = malloc(2 * cut->vertex_count * sizeof *out);
    texopt_distortion_reduce_report rep;
    char err[256];
    CHECK_OK(texopt_distortion_reduce(cut, reference, start, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.refused, 0);
    CHECK(rep.rounds >= 1);
    double before = texopt_distortion_relative(cut, reference, start);
    double after = texopt_distortion_relative(cut, reference, out);
    CHECK_MSG(before > 1.01 && after - 1 < 0.5 * (before - 1), "distortion %.4f -> %.4f in %d rounds", before, after,
              rep.rounds);
    CHECK(fabs(after - rep.distortion) < 1e-12 && fabs(before - rep.distortion_start) < 1e-12);
    size_t reversed = 0, within, between, outside = 0;
    double area = layout_area(cut, out, &reversed);
    CHECK_EQ_INT(reversed, 0);
    CHECK_OK(texopt_count_overlap(cut, out, &within, &between, err, sizeof err), err);
    CHECK_EQ_INT(within, 0);
    CHECK_EQ_INT(between, 0);
    for (size_t v = 0; v < cut->vertex_count; v++)
        outside += out[2 * v] < rep.box[0] || out[2 * v] > rep.box[2] || out[2 * v + 1] < rep.box[1] ||
                   out[2 * v + 1] > rep.box[3];
    CHECK_EQ_INT(outside, 0);
    /* the box: the start's bounding box, scaled, grown by delta then by delta_step a round */
    double b0[4];
    bounding_box(cut, start, b0);
    double grow = rep.scale * TEXOPT_REDUCE_DELTA * pow(1 + TEXOPT_REDUCE_DELTA_STEP, rep.rounds - 1);
    double bw = rep.box[2] - rep.box[0], bh = rep.box[3] - rep.box[1];
    CHECK_MSG(fabs(bw / ((b0[2] - b0[0]) * grow) - 1) < 1e-9 && fabs(bh / ((b0[3] - b0[1]) * grow) - 1) < 1e-9,
              "box %.3f x %.3f, start %.3f x %.3f, scale %.4f, %d rounds", bw, bh, b0[2] - b0[0], b0[3] - b0[1],
              rep.scale, rep.rounds);
    CHECK_MSG(rep.efficiency >= area / (bw * bh) - 1e-12, "efficiency %.4f below the box's bound %.4f", rep.efficiency,
              area / (bw * bh));
    /* every chart at most its reference area after the initial scale */
    CHECK(rep.scale > 0.8 && rep.scale <= 1.0 + 1e-12);
    free(out);
    free(start);
    free(reference);
    texopt_mesh_destroy(cut);
}

TEST(a_packing_bound_out_of_reach_stops_before_the_first_round)
{
    double *start = NULL;
    double *reference = NULL;
    texopt_mesh *cut = NULL;
    packed_pieces(&cut, &reference, &start);
    CHECK(cut != NULL);
    double *out = malloc(2 * cut->vertex_count * sizeof *out);
    texopt_distortion_reduce_options o = {0};
    o.min_efficiency = 0.999;
    texopt_distortion_reduce_report rep;
    char err[256];
    CHECK_OK(texopt_distortion_reduce(cut, reference, start, &o, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.rounds, 0);
    CHECK_EQ_INT(rep.refused, 0);
    for (size_t i = 0; i < 2 * cut->vertex_count; i++)
        CHECK(fabs(out[i] - rep.scale * start[i]) < 1e-12);
    free(out);
    free(start);
    free(reference);
    texopt_mesh_destroy(cut);
}

TEST(pieces_over_each_other_are_refused_and_returned_as_they_came)
{
    double *start = NULL;
    double *reference = NULL;
    texopt_mesh *cut = NULL;
    packed_pieces(&cut, &reference, &start);
    CHECK(cut != NULL);
    double lo[2][2] = {{INFINITY, INFINITY}, {INFINITY, INFINITY}};
    for (size_t k = 0; k < 3 * cut->triangle_count; k++)
        for (int a = 0; a < 2; a++)
            lo[cut->chart_of[k / 3]][a] = fmin(lo[cut->chart_of[k / 3]][a], start[2 * (size_t)cut->triangle[k] + a]);
    for (size_t v = 0; v < cut->vertex_count; v++) /* the second piece's corner onto the first's */
        for (size_t k = 0; k < 3 * cut->triangle_count; k++)
            if (cut->triangle[k] == v && cut->chart_of[k / 3] == 1) {
                start[2 * v] += lo[0][0] - lo[1][0];
                start[2 * v + 1] += lo[0][1] - lo[1][1];
                break;
            }
    double *out = malloc(2 * cut->vertex_count * sizeof *out);
    texopt_distortion_reduce_report rep;
    char err[256];
    CHECK_OK(texopt_distortion_reduce(cut, reference, start, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.refused, 1);
    CHECK(memcmp(out, start, 2 * cut->vertex_count * sizeof *out) == 0);
    free(out);
    free(start);
    free(reference);
    texopt_mesh_destroy(cut);
}

/* Two squares of two triangles, squeezed to 0.8 of their width in the start, and a folded
 * chart (two triangles over one edge, one of each orientation, folded in the input too):
 * the fold cannot be boxed, so it is moved right of the box and the squares are reduced
 * without it. */
TEST(a_folded_chart_is_left_out_of_the_box)
{
    texopt_mesh *m = handmesh_alloc(12, 6);
    CHECK(m != NULL);
    m->chart_count = 3;
    double texel[24] = {0, 0, 8, 0, 8, 8, 0, 8, 12, 0, 20, 0, 20, 8, 12, 8, 24, 0, 32, 0, 28, 8, 28, 5};
    uint32_t tri[18] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 9, 8, 11};
    memcpy(m->texel, texel, sizeof texel);
    memcpy(m->triangle, tri, sizeof tri);
    for (size_t v = 0; v < 12; v++) {
        m->position[3 * v] = texel[2 * v];
        m->position[3 * v + 1] = texel[2 * v + 1];
    }
    uint32_t chart[6] = {0, 0, 1, 1, 2, 2};
    memcpy(m->chart_of, chart, sizeof chart);
    handmesh_finish(m);
    double start[24];
    memcpy(start, texel, sizeof start);
    for (size_t v = 0; v < 8; v++) /* the squares squeezed across */
        start[2 * v] = (v < 4 ? 0 : 12) + 0.8 * (texel[2 * v] - (v < 4 ? 0 : 12));
    double out[24];
    texopt_distortion_reduce_report rep;
    char err[256];
    CHECK_OK(texopt_distortion_reduce(m, m->texel, start, NULL, out, &rep, NULL, err, sizeof err), err);
    CHECK_EQ_INT(rep.refused, 0);
    CHECK_EQ_INT(rep.charts_unboxed, 1);
    CHECK(rep.rounds >= 1);
    for (size_t v = 0; v < 8; v++)
        CHECK(out[2 * v] >= rep.box[0] && out[2 * v] <= rep.box[2] && out[2 * v + 1] >= rep.box[1] &&
              out[2 * v + 1] <= rep.box[3]);
    for (size_t v = 8; v < 12; v++)
        CHECK_MSG(out[2 * v] > rep.box[2], "fold vertex %zu at x %.2f, box ends at %.2f", v, out[2 * v], rep.box[2]);
    CHECK_MSG(rep.distortion < rep.distortion_start, "distortion %.4f -> %.4f", rep.distortion_start, rep.distortion);
    texopt_mesh_destroy(m);
}

#define SQUARE_CELLS 4
#define SQUARE_CELL 2.0
#define SQUARE_SIDE (SQUARE_CELLS * SQUARE_CELL)
#define SQUARES_APART 3.5
#define GAP 2.0

/* Two squares of SQUARE_CELLS^2 cells, charts 0 (left) and 1 (right, SQUARES_APART to its
 * right); input texels and start the same; reference: the left as it is, the right scaled
 * by 2 about its centre (caller frees both). */
static texopt_mesh *pressed_squares(double **reference, double **start)
{
    size_t side = SQUARE_CELLS + 1, nv = 2 * side * side, nt = 4 * SQUARE_CELLS * SQUARE_CELLS;
    texopt_mesh *m = handmesh_alloc(nv, nt);
    *reference = malloc(2 * nv * sizeof **reference);
    *start = malloc(2 * nv * sizeof **start);
    if (!m || !*reference || !*start)
        return NULL;
    size_t t = 0;
    for (size_t c = 0; c < 2; c++) {
        double x0 = c * (SQUARE_SIDE + SQUARES_APART), centre = x0 + 0.5 * SQUARE_SIDE;
        for (size_t j = 0; j < side; j++)
            for (size_t i = 0; i < side; i++) {
                size_t v = c * side * side + j * side + i;
                double x = x0 + SQUARE_CELL * (double)i, y = SQUARE_CELL * (double)j, k = c ? 2.0 : 1.0;
                m->texel[2 * v] = (*start)[2 * v] = m->position[3 * v] = x;
                m->texel[2 * v + 1] = (*start)[2 * v + 1] = m->position[3 * v + 1] = y;
                (*reference)[2 * v] = centre + k * (x - centre);
                (*reference)[2 * v + 1] = 0.5 * SQUARE_SIDE + k * (y - 0.5 * SQUARE_SIDE);
            }
        for (size_t j = 0; j < SQUARE_CELLS; j++)
            for (size_t i = 0; i < SQUARE_CELLS; i++) {
                uint32_t a = (uint32_t)(c * side * side + j * side + i), b = a + 1, d = a + (uint32_t)side, e = d + 1;
                uint32_t tri[6] = {a, b, e, a, e, d};
                memcpy(m->triangle + 3 * t, tri, sizeof tri);
                m->chart_of[t] = m->chart_of[t + 1] = (uint32_t)c;
                t += 2;
            }
    }
    m->chart_count = 2;
    handmesh_finish(m);
    return m;
}

/* The squares reduced with a gap layer of width `layer` (0: none): the smallest distance
 * between them after. */
static void reduce_squares(double layer, double *apart, texopt_distortion_reduce_report *rep)
{
    char err[256];
    double *reference = NULL, *start = NULL;
    texopt_mesh *m = pressed_squares(&reference, &start);
    CHECK(m != NULL);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    texopt_distortion_reduce_options o = {0};
    o.gap_layer = layer;
    CHECK_OK(texopt_distortion_reduce(m, reference, start, &o, out, rep, NULL, err, sizeof err), err);
    CHECK_OK(texopt_chart_gap(m, out, NULL, apart, err, sizeof err), err);
    size_t reversed = 0;
    layout_area(m, out, &reversed);
    CHECK_EQ_INT(reversed, 0);
    free(out);
    free(reference);
    free(start);
    texopt_mesh_destroy(m);
}

TEST(a_gap_layer_keeps_squares_pressed_together_the_gap_apart)
{
    texopt_distortion_reduce_report without, with;
    double apart_without = 0, apart_with = 0;
    reduce_squares(0.0, &apart_without, &without);
    reduce_squares(0.75 * GAP, &apart_with, &with); /* a quarter spare for the squeeze */
    CHECK_MSG(!without.refused && !with.refused && without.rounds >= 1 && with.rounds >= 1, "refused %d %d",
              without.refused, with.refused);
    CHECK_MSG(apart_without < 0.5 * GAP, "without a layer %.3f apart (%d rounds)", apart_without, without.rounds);
    CHECK_MSG(apart_with >= GAP, "with a layer %.3f apart (%d rounds), %zu charts without", apart_with, with.rounds,
              with.charts_without_gap);
    CHECK_EQ_INT(with.charts_without_gap, 0);
    CHECK_MSG(with.distortion < with.distortion_start, "distortion %.4f -> %.4f", with.distortion_start,
              with.distortion);
}

/* The bound holds a packing once it reaches it; a start short of it (the squares fill little
 * of their box) may still gain, so the reduction runs toward it instead of stopping. */
TEST(a_start_short_of_the_bound_may_gain_but_not_lose)
{
    char err[256];
    double *reference = NULL, *start = NULL;
    texopt_mesh *m = pressed_squares(&reference, &start);
    CHECK(m != NULL);
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    texopt_distortion_reduce_options o = {0};
    o.min_efficiency = 0.999;
    texopt_distortion_reduce_report rep;
    CHECK_OK(texopt_distortion_reduce(m, reference, start, &o, out, &rep, NULL, err, sizeof err), err);
    CHECK_MSG(rep.rounds >= 1 && rep.efficiency > rep.efficiency_start, "%d rounds, efficiency %.4f -> %.4f",
              rep.rounds, rep.efficiency_start, rep.efficiency);
    CHECK(rep.efficiency < o.min_efficiency);
    free(out);
    free(reference);
    free(start);
    texopt_mesh_destroy(m);
}
