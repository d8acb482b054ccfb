/* Tests of chart_reshape.c on generated charts: an L-shaped and a disc-shaped chart fill
 * more of their boxes after the reshape, only as much as the goal asks, without a flipped
 * triangle; charts already at the goal, folded charts and the triangles' connectivity stay
 * as they were; a hole is not pulled open; bad requests are refused. Meshes are built by
 * hand (handmesh.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "chart_reshape.h"
#include "disc_charts.h"
#include "distortion.h"
#include "handmesh.h"
#include "test.h"

/* n x n grid cells of `cell` texels at x0, cells with keep(i, j) only, two triangles each;
 * vertices and triangles appended from *v, *t; chart `chart`. */
typedef int (*cell_rule)(int i, int j, int n);

static int whole(int i, int j, int n)
{
    (void)i, (void)j, (void)n;
    return 1;
}

static int l_shape(int i, int j, int n)
{
    return !(i >= n / 2 && j >= n / 2);
}

static size_t count_cells(int n, cell_rule keep)
{
    size_t k = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            k += keep(i, j, n) != 0;
    return k;
}

static void add_grid(texopt_mesh *m, size_t *v, size_t *t, int n, double cell, double x0, cell_rule keep,
                     uint32_t chart)
{
    size_t base = *v;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t k = base + (size_t)j * (n + 1) + i;
            m->texel[2 * k] = x0 + i * cell;
            m->texel[2 * k + 1] = j * cell;
            m->position[3 * k] = m->texel[2 * k] / 16.0;
            m->position[3 * k + 1] = m->texel[2 * k + 1] / 16.0;
        }
    *v += (size_t)(n + 1) * (n + 1);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            if (!keep(i, j, n))
                continue;
            uint32_t a = (uint32_t)(base + (size_t)j * (n + 1) + i), b = a + 1, d = a + (uint32_t)(n + 1), e = d + 1;
            uint32_t tris[6] = {a, b, e, a, e, d};
            memcpy(m->triangle + 3 * *t, tris, sizeof tris);
            m->chart_of[*t] = m->chart_of[*t + 1] = chart;
            *t += 2;
        }
}

/* An L-shaped chart (a 12 x 12 grid without its top-right quarter: fill 0.75) and, to its
 * right, a full square chart (fill 1). */
static texopt_mesh *l_and_square(void)
{
    int n = 12;
    size_t per_v = (size_t)(n + 1) * (n + 1);
    texopt_mesh *m = handmesh_alloc(2 * per_v, 2 * (count_cells(n, l_shape) + count_cells(n, whole)));
    m->chart_count = 2;
    size_t v = 0, t = 0;
    add_grid(m, &v, &t, n, 4.0, 0.0, l_shape, 0);
    add_grid(m, &v, &t, n, 4.0, 80.0, whole, 1);
    handmesh_finish(m);
    return m;
}

/* Area over box area of the triangles of chart c under layout x. */
static double box_fill(const texopt_mesh *m, const double *x, uint32_t c)
{
    double area = 0, lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t t = 0; t < m->triangle_count; t++) {
        if (m->chart_of[t] != c)
            continue;
        const uint32_t *v = m->triangle + 3 * t;
        area += 0.5 * fabs(handmesh_doubled_area(x, v, 2));
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], x[2 * v[j] + a]);
                hi[a] = fmax(hi[a], x[2 * v[j] + a]);
            }
    }
    return area / ((hi[0] - lo[0]) * (hi[1] - lo[1]));
}

static size_t flipped(const texopt_mesh *m, const double *x)
{
    size_t n = 0;
    for (size_t t = 0; t < m->triangle_count; t++)
        n += handmesh_doubled_area(x, m->triangle + 3 * t, 2) * m->area_texel[t] <= 0.0;
    return n;
}

static int chart_unchanged(const texopt_mesh *m, const double *a, const double *b, uint32_t c)
{
    for (size_t t = 0; t < m->triangle_count; t++)
        if (m->chart_of[t] == c)
            for (int j = 0; j < 3; j++) {
                uint32_t v = m->triangle[3 * t + j];
                if (a[2 * v] != b[2 * v] || a[2 * v + 1] != b[2 * v + 1])
                    return 0;
            }
    return 1;
}

/* The mesh's own layout reshaped to `goal` into a new array (*out). */
static texopt_status reshape_to(const texopt_mesh *m, double goal, double **out, texopt_reshape_report *rep, char *err,
                                size_t err_len)
{
    *out = malloc(2 * m->vertex_count * sizeof **out);
    texopt_reshape_options o = {.box_fill = goal, .threads = 1};
    return texopt_chart_reshape(m, m->texel, NULL, &o, *out, rep, err, err_len);
}

/* Points of a quarter-texel grid over chart c that lie strictly inside two of its
 * triangles under layout x: 0 when the chart does not overlap itself. */
static size_t doubly_covered(const texopt_mesh *m, const double *x, uint32_t c)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int j = 0; j < 3 && m->chart_of[t] == c; j++)
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], x[2 * m->triangle[3 * t + j] + a]);
                hi[a] = fmax(hi[a], x[2 * m->triangle[3 * t + j] + a]);
            }
    size_t twice = 0;
    for (double py = lo[1] + 0.125; py < hi[1]; py += 0.25)
        for (double px = lo[0] + 0.125; px < hi[0]; px += 0.25) {
            int inside = 0;
            for (size_t t = 0; t < m->triangle_count && inside < 2; t++) {
                if (m->chart_of[t] != c)
                    continue;
                const uint32_t *v = m->triangle + 3 * t;
                double s = handmesh_doubled_area(x, v, 2) > 0 ? 1 : -1;
                int in = 1;
                for (int e = 0; e < 3 && in; e++) {
                    const double *p = x + 2 * v[e], *q = x + 2 * v[(e + 1) % 3];
                    in = s * ((q[0] - p[0]) * (py - p[1]) - (px - p[0]) * (q[1] - p[1])) > 0;
                }
                inside += in;
            }
            twice += inside >= 2;
        }
    return twice;
}

TEST(a_disc_fills_more_of_its_box_and_no_more_than_asked)
{
    texopt_mesh *m = disc_charts(1, 8, 48, 0);
    double before = box_fill(m, m->texel, 0);
    CHECK(before > 0.77 && before < 0.79); /* pi / 4 for the polygon */
    texopt_reshape_report rep;
    char err[256];
    double *low, *high;
    CHECK_OK(reshape_to(m, 0.85, &low, &rep, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_reshaped, 1);
    CHECK_EQ_INT(rep.charts_reaching, 1);
    CHECK(rep.fill_after > rep.fill_before);
    double fill_low = box_fill(m, low, 0);
    CHECK_MSG(fill_low >= 0.85 && fill_low < 0.9, "disc fill %.3f -> %.3f for goal 0.85", before, fill_low);
    CHECK_OK(reshape_to(m, 0.97, &high, &rep, err, sizeof err), err);
    double fill_high = box_fill(m, high, 0);
    CHECK_MSG(fill_high > fill_low + 0.03, "goal 0.97 gave %.3f, goal 0.85 %.3f", fill_high, fill_low);
    CHECK_EQ_INT((int)flipped(m, low), 0);
    CHECK_EQ_INT((int)flipped(m, high), 0);
    CHECK_EQ_INT((int)doubly_covered(m, high, 0), 0);
    texopt_distortion d;
    CHECK_OK(texopt_distortion_measure(m, high, &d, err, sizeof err), err);
    CHECK_EQ_INT((int)d.flipped, 0);
    CHECK(isfinite(d.symmetric_dirichlet));
    free(low);
    free(high);
    texopt_mesh_destroy(m);
}

/* Filling an L's notch from both of its sides sweeps the two sides into each other: the
 * stronger pulls fold the chart over itself, and the reshape must stop before they do. */
TEST(an_l_shaped_chart_never_folds_over_itself)
{
    texopt_mesh *m = l_and_square();
    CHECK_NEAR(box_fill(m, m->texel, 0), 0.75, 1e-12);
    texopt_reshape_report rep;
    char err[256];
    double *out;
    CHECK_OK(reshape_to(m, 0.95, &out, &rep, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_below, 1);
    CHECK_EQ_INT(rep.charts_reshaped, 1);
    CHECK_EQ_INT((int)doubly_covered(m, out, 0), 0);
    CHECK(box_fill(m, out, 0) >= 0.75);
    CHECK_EQ_INT((int)flipped(m, out), 0);
    CHECK(chart_unchanged(m, m->texel, out, 1)); /* the square was at the goal already */
    free(out);
    texopt_mesh_destroy(m);
}

/* Area of the hole of an annulus: the polygon of its inner ring (vertices 0 .. segments). */
static double hole_area(const double *x, int segments)
{
    double a = 0;
    for (int s = 0; s < segments; s++) {
        const double *p = x + 2 * s, *q = x + 2 * ((s + 1) % segments);
        a += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * fabs(a);
}

TEST(a_hole_is_not_pulled_toward_the_box)
{
    texopt_mesh *m = disc_charts(1, 6, 48, 15.0);
    texopt_reshape_report rep;
    char err[256];
    double *out;
    CHECK_OK(reshape_to(m, 0.95, &out, &rep, err, sizeof err), err);
    CHECK(box_fill(m, out, 0) > box_fill(m, m->texel, 0) + 0.05);
    /* Pulled like the outer ring, the inner ring would be dragged onto the box sides and
     * the hole would grow several times over. */
    double before = hole_area(m->texel, 48), after = hole_area(out, 48);
    CHECK_MSG(after < 1.5 * before, "hole %.1f -> %.1f texels", before, after);
    CHECK_EQ_INT((int)flipped(m, out), 0);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(a_folded_chart_keeps_its_shape)
{
    texopt_mesh *m = l_and_square();
    /* One triangle of the L wound the other way in the input: the chart holds both
     * orientations, like mirrored halves joined along a fold. */
    uint32_t *tri = m->triangle + 3 * 5;
    uint32_t swap = tri[1];
    tri[1] = tri[2];
    tri[2] = swap;
    handmesh_finish(m);
    texopt_reshape_report rep;
    char err[256];
    double *out;
    CHECK_OK(reshape_to(m, 0.9, &out, &rep, err, sizeof err), err);
    CHECK(chart_unchanged(m, m->texel, out, 0));
    CHECK_EQ_INT(rep.charts_below, 1);
    CHECK_EQ_INT(rep.charts_reshaped, 0);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(a_kept_chart_keeps_its_shape)
{
    /* The L is pulled toward its box unless the caller keeps it (a sharing group). */
    texopt_mesh *m = l_and_square();
    const uint8_t keep[2] = {1, 0};
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    texopt_reshape_options o = {.box_fill = 0.9, .threads = 1, .keep = keep};
    texopt_reshape_report rep;
    char err[256];
    CHECK_OK(texopt_chart_reshape(m, m->texel, NULL, &o, out, &rep, err, sizeof err), err);
    CHECK(chart_unchanged(m, m->texel, out, 0));
    CHECK_EQ_INT(rep.charts_below, 1);
    CHECK_EQ_INT(rep.charts_reshaped, 0);
    o.keep = NULL;
    CHECK_OK(texopt_chart_reshape(m, m->texel, NULL, &o, out, &rep, err, sizeof err), err);
    CHECK_EQ_INT(rep.charts_reshaped, 1);
    free(out);
    texopt_mesh_destroy(m);
}

TEST(bad_requests_are_refused)
{
    texopt_mesh *m = l_and_square();
    char err[256] = "";
    double *out = malloc(2 * m->vertex_count * sizeof *out);
    texopt_reshape_options o = {.box_fill = 0.0, .threads = 1};
    CHECK(texopt_chart_reshape(m, m->texel, NULL, &o, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "box fill") != NULL);
    o.box_fill = 1.5;
    CHECK(texopt_chart_reshape(m, m->texel, NULL, &o, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    o.box_fill = NAN;
    CHECK(texopt_chart_reshape(m, m->texel, NULL, &o, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    o.box_fill = 0.9;
    CHECK(texopt_chart_reshape(m, m->texel, NULL, &o, m->texel, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    m->chart_of[3] = 7;
    CHECK(texopt_chart_reshape(m, m->texel, NULL, &o, out, NULL, err, sizeof err) == TEXOPT_E_INVALID_ARGUMENT);
    CHECK(strstr(err, "chart") != NULL);
    free(out);
    texopt_mesh_destroy(m);
}
