/* atlas_refine.c - charts deformed toward axis-aligned shapes; see atlas_refine.h. */
#include "atlas_refine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "axis_angles.h"
#include "axis_deform.h"
#include "param_chart.h"
#include "vec2.h"

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double texopt_atlas_boundary_length(const texopt_mesh *mesh, const double *texel)
{
    uint32_t *edge = NULL;
    size_t n = 0;
    double length = 0;
    if (texopt_param_boundary_edges(mesh->triangle, mesh->triangle_count, &edge, &n, NULL, 0) == TEXOPT_OK)
        for (size_t e = 0; e < n; e++)
            length += hypot(texel[2 * (size_t)edge[2 * e + 1]] - texel[2 * (size_t)edge[2 * e]],
                            texel[2 * (size_t)edge[2 * e + 1] + 1] - texel[2 * (size_t)edge[2 * e] + 1]);
    free(edge);
    return length;
}

/* One chart in local vertex numbers, mirrored when clockwise so that every triangle is
 * counter-clockwise, as axis_deform.h wants it. */
typedef struct chart_problem {
    size_t nv, nt;
    uint32_t *vertex; /* local -> mesh vertex */
    uint32_t *tri;    /* 3 per triangle, local, counter-clockwise */
    double *rest, *xy;
    double *position; /* rest with z = 0, the chart for param_chart.h */
    double mirror;    /* +1, or -1 when y was negated */
    double area;
} chart_problem;

/* Fills p with the chart's triangles tris[0..nt); local (per mesh vertex, UINT32_MAX) is
 * the scratch numbering, left as it was found. Returns 0 when the chart has a triangle
 * without area or against its orientation. */
static int chart_build(const texopt_mesh *mesh, const double *texel, const uint32_t *tris, size_t nt, uint32_t *local,
                       chart_problem *p)
{
    double sum = 0;
    int ok = 1;
    for (size_t i = 0; i < nt; i++) {
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[i];
        sum += texopt_signed_area(texel + 2 * (size_t)v[0], texel + 2 * (size_t)v[1], texel + 2 * (size_t)v[2]);
    }
    p->mirror = sum < 0 ? -1.0 : 1.0;
    p->area = fabs(sum);
    p->nt = nt;
    p->nv = 0;
    for (size_t i = 0; i < nt; i++) {
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[i];
        const double *a = texel + 2 * (size_t)v[0], *b = texel + 2 * (size_t)v[1], *c = texel + 2 * (size_t)v[2];
        if (texopt_texel_triangle_degenerate(a, b, c) || !(p->mirror * texopt_signed_area(a, b, c) > 0))
            ok = 0;
        for (int k = 0; k < 3; k++) {
            if (local[v[k]] == UINT32_MAX) {
                local[v[k]] = (uint32_t)p->nv;
                p->vertex[p->nv++] = v[k];
            }
        }
        for (int k = 0; k < 3; k++)
            p->tri[3 * i + k] = local[v[k]];
    }
    for (size_t i = 0; i < p->nv; i++) {
        local[p->vertex[i]] = UINT32_MAX;
        p->rest[2 * i] = texel[2 * (size_t)p->vertex[i]];
        p->rest[2 * i + 1] = p->mirror * texel[2 * (size_t)p->vertex[i] + 1];
        p->position[3 * i] = p->rest[2 * i];
        p->position[3 * i + 1] = p->rest[2 * i + 1];
        p->position[3 * i + 2] = 0;
    }
    return ok;
}

/* The boundary loop of a disk chart (param_chart.h; counter-clockwise, *count vertices, the
 * caller frees it), or NULL when the chart is not a disk or on no memory. It starts at the
 * first boundary edge in triangle order, as the refinement's loops always have: the angles
 * and the deformation round differently from another start, and refined layouts stay as
 * they were. */
static uint32_t *chart_loop(const chart_problem *p, size_t *count)
{
    char err[256];
    texopt_param_chart chart = {p->nv, p->position, p->nt, p->tri};
    texopt_param_boundary *boundary = NULL;
    uint32_t *edge = NULL, *loop = NULL;
    size_t n = 0;
    if (texopt_param_boundary_create(&boundary, &chart, err, sizeof err) == TEXOPT_OK &&
        texopt_param_boundary_edges(p->tri, p->nt, &edge, &n, err, sizeof err) == TEXOPT_OK)
        loop = malloc(boundary->count * sizeof *loop);
    if (loop) {
        size_t first = 0;
        while (boundary->vertex[first] != edge[0])
            first++;
        for (size_t i = 0; i < boundary->count; i++)
            loop[i] = boundary->vertex[(first + i) % boundary->count];
        *count = boundary->count;
    }
    free(edge);
    texopt_param_boundary_destroy(boundary);
    return loop;
}

enum { DEFORMED = 1, REFUSED = 0, TURNS_TOO_FAR = -1 };

/* Deforms one chart; returns DEFORMED when p->xy holds the refined chart, with its
 * distortion and angle error in rep, TURNS_TOO_FAR for a keep_angle chart whose turn is
 * past TEXOPT_ATLAS_REFINE_MAX_TURN. */
static int chart_deform(chart_problem *p, int keep_angle, texopt_axis_deform_report *rep)
{
    size_t nb = 0;
    uint32_t *loop = chart_loop(p, &nb);
    double *pts = loop && nb >= 4 ? malloc(2 * nb * sizeof *pts) : NULL;
    if (!pts) {
        free(loop);
        return REFUSED;
    }
    for (size_t i = 0; i < nb; i++)
        memcpy(pts + 2 * i, p->rest + 2 * (size_t)loop[i], 2 * sizeof *pts);
    char err[256];
    texopt_axis_angles angles;
    memset(&angles, 0, sizeof angles);
    texopt_status st = texopt_axis_angles_compute(pts, nb, &angles, err, sizeof err);
    int turns_too_far = st == TEXOPT_OK && keep_angle && fabs(angles.rotation) > TEXOPT_ATLAS_REFINE_MAX_TURN;
    if (st == TEXOPT_OK && !turns_too_far)
        st = texopt_axis_deform(p->nv, p->rest, p->nt, p->tri, loop, &angles, p->xy, rep, err, sizeof err);
    texopt_axis_angles_destroy(&angles);
    free(loop);
    free(pts);
    if (turns_too_far)
        return TURNS_TOO_FAR;
    return st == TEXOPT_OK && isfinite(rep->distortion) ? DEFORMED : REFUSED;
}

/* Triangles grouped by chart: order (triangle_count) and start (chart_count + 1). */
static int charts_of_triangles(const texopt_mesh *mesh, uint32_t *order, size_t *start)
{
    memset(start, 0, (mesh->chart_count + 1) * sizeof *start);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        start[mesh->chart_of[t] + 1]++;
    for (size_t c = 0; c < mesh->chart_count; c++)
        start[c + 1] += start[c];
    size_t *fill = malloc((mesh->chart_count ? mesh->chart_count : 1) * sizeof *fill);
    if (!fill)
        return 0;
    memcpy(fill, start, mesh->chart_count * sizeof *fill);
    for (size_t t = 0; t < mesh->triangle_count; t++)
        order[fill[mesh->chart_of[t]]++] = (uint32_t)t;
    free(fill);
    return 1;
}

/* The work room of a pass over a layout's charts: triangles grouped by chart (order,
 * start), the scratch numbering local (all UINT32_MAX) and one chart_problem. */
typedef struct chart_pass {
    uint32_t *order, *local;
    size_t *start;
    chart_problem p;
} chart_pass;

static void chart_pass_free(chart_pass *w)
{
    free(w->order);
    free(w->local);
    free(w->start);
    free(w->p.vertex);
    free(w->p.tri);
    free(w->p.rest);
    free(w->p.xy);
    free(w->p.position);
}

static int chart_pass_alloc(chart_pass *w, const texopt_mesh *mesh)
{
    size_t nv = mesh->vertex_count ? mesh->vertex_count : 1, nt = mesh->triangle_count ? mesh->triangle_count : 1;
    memset(w, 0, sizeof *w);
    w->order = malloc(nt * sizeof *w->order);
    w->local = malloc(nv * sizeof *w->local);
    w->start = malloc((mesh->chart_count + 1) * sizeof *w->start);
    w->p.vertex = malloc(nv * sizeof *w->p.vertex);
    w->p.tri = malloc(3 * nt * sizeof *w->p.tri);
    w->p.rest = malloc(2 * nv * sizeof *w->p.rest);
    w->p.xy = malloc(2 * nv * sizeof *w->p.xy);
    w->p.position = malloc(3 * nv * sizeof *w->p.position);
    if (!w->order || !w->local || !w->start || !w->p.vertex || !w->p.tri || !w->p.rest || !w->p.xy || !w->p.position ||
        !charts_of_triangles(mesh, w->order, w->start))
        return 0;
    memset(w->local, 0xff, nv * sizeof *w->local);
    return 1;
}

texopt_status texopt_atlas_refine(const texopt_mesh *mesh, const double *texel, const uint8_t *keep_shape,
                                  const uint8_t *keep_angle, double max_distortion, double *texel_out,
                                  texopt_atlas_refine_report *report, const texopt_monitor *monitor, char *err,
                                  size_t err_len)
{
    double t0 = now_seconds();
    texopt_atlas_refine_report rep = {0};
    memcpy(texel_out, texel, 2 * mesh->vertex_count * sizeof *texel_out);
    chart_pass w;
    texopt_status st = chart_pass_alloc(&w, mesh)
                           ? TEXOPT_OK
                           : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "atlas refinement: no memory");
    uint32_t *order = w.order, *local = w.local;
    size_t *start = w.start;
    chart_problem p = w.p;
    double weighted = 0, area = 0;
    for (size_t c = 0; st == TEXOPT_OK && c < mesh->chart_count; c++) {
        if (texopt_monitor_canceled(monitor)) {
            st = texopt_fail(err, err_len, TEXOPT_E_CANCELED, "canceled");
            break;
        }
        int built = chart_build(mesh, texel, order + start[c], start[c + 1] - start[c], local, &p);
        texopt_axis_deform_report dr = {0};
        area += p.area;
        int deformed =
            built && !(keep_shape && keep_shape[c]) ? chart_deform(&p, keep_angle && keep_angle[c], &dr) : REFUSED;
        if (deformed != DEFORMED) {
            rep.charts_skipped++;
            rep.charts_kept_angle += deformed == TURNS_TOO_FAR;
            weighted += p.area;
            continue;
        }
        if (max_distortion > 0 && dr.distortion > max_distortion) {
            rep.charts_skipped++;
            rep.charts_too_distorted++;
            weighted += p.area;
            continue;
        }
        rep.charts_refined++;
        weighted += p.area * dr.distortion;
        rep.max_angle_error = fmax(rep.max_angle_error, dr.max_angle_error);
        for (size_t i = 0; i < p.nv; i++) {
            texel_out[2 * (size_t)p.vertex[i]] = p.xy[2 * i];
            texel_out[2 * (size_t)p.vertex[i] + 1] = p.mirror * p.xy[2 * i + 1];
        }
    }
    if (st == TEXOPT_OK) {
        rep.distortion = area > 0 ? weighted / area : 1.0;
        rep.boundary_before = texopt_atlas_boundary_length(mesh, texel);
        rep.boundary_after = texopt_atlas_boundary_length(mesh, texel_out);
        rep.seconds = now_seconds() - t0;
        if (report)
            *report = rep;
    }
    chart_pass_free(&w);
    return st;
}

/* The pieces of one chart (p, laid out counter-clockwise) into cut; 0 when it stays whole. */
static int chart_pieces(const chart_problem *p, const texopt_chart_cut_options *opt, texopt_chart_cut *cut)
{
    size_t nb = 0;
    uint32_t *loop = chart_loop(p, &nb);
    double *pts = loop && nb >= 4 ? malloc(2 * nb * sizeof *pts) : NULL;
    int ok = 0;
    char err[256];
    texopt_axis_angles angles;
    memset(&angles, 0, sizeof angles);
    for (size_t i = 0; pts && i < nb; i++)
        memcpy(pts + 2 * i, p->rest + 2 * (size_t)loop[i], 2 * sizeof *pts);
    if (pts && texopt_axis_angles_compute(pts, nb, &angles, err, sizeof err) == TEXOPT_OK &&
        fabs(angles.rotation) <= TEXOPT_ATLAS_REFINE_MAX_TURN &&
        texopt_chart_cut_compute(p->nv, p->rest, p->nt, p->tri, loop, angles.theta, nb, opt, cut, err, sizeof err) ==
            TEXOPT_OK) {
        double r = cut->polygon_area_ratio;
        ok = cut->piece_count > 1 && r > 1 / TEXOPT_ATLAS_CUT_AREA_RATIO && r < TEXOPT_ATLAS_CUT_AREA_RATIO;
        if (!ok)
            texopt_chart_cut_destroy(cut);
    }
    texopt_axis_angles_destroy(&angles);
    free(loop);
    free(pts);
    return ok;
}

texopt_status texopt_atlas_cut(const texopt_mesh *mesh, const double *texel, const uint8_t *keep_shape,
                               const texopt_chart_cut_options *opt, uint32_t *piece_of, size_t *piece_count,
                               texopt_atlas_refine_report *report, const texopt_monitor *monitor, char *err,
                               size_t err_len)
{
    double t0 = now_seconds();
    chart_pass w;
    texopt_status st =
        chart_pass_alloc(&w, mesh) ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "atlas cut: no memory");
    uint32_t *order = w.order, *local = w.local;
    size_t *start = w.start, pieces = 0;
    chart_problem p = w.p;
    texopt_atlas_refine_report rep = report ? *report : (texopt_atlas_refine_report){0};
    rep.charts_cut = rep.cuts = 0;
    for (size_t c = 0; st == TEXOPT_OK && c < mesh->chart_count; c++) {
        if (texopt_monitor_canceled(monitor)) {
            st = texopt_fail(err, err_len, TEXOPT_E_CANCELED, "canceled");
            break;
        }
        const uint32_t *tris = order + start[c];
        size_t n = start[c + 1] - start[c];
        texopt_chart_cut cut = {0};
        int built = chart_build(mesh, texel, tris, n, local, &p);
        if (built && !(keep_shape && keep_shape[c]) && chart_pieces(&p, opt, &cut)) {
            for (size_t i = 0; i < n; i++)
                piece_of[tris[i]] = (uint32_t)(pieces + cut.piece_of[i]);
            pieces += cut.piece_count;
            rep.charts_cut++;
            rep.cuts += cut.trail_count;
            texopt_chart_cut_destroy(&cut);
            continue;
        }
        for (size_t i = 0; i < n; i++)
            piece_of[tris[i]] = (uint32_t)pieces;
        pieces++;
    }
    if (st == TEXOPT_OK) {
        *piece_count = pieces;
        rep.pieces = pieces;
        rep.cut_seconds = now_seconds() - t0;
        if (report)
            *report = rep;
    }
    chart_pass_free(&w);
    return st;
}
