/* scaffold.c - scaffold triangles around charts for a bijective stage 2 (scaffold.h).
 *
 * Per box: the boundary edges of its charts (edges of one triangle) and the box's four
 * edges are the segments of a constrained triangulation of the boundary vertices and the
 * box corners (no Steiner points, so every scaffold vertex is a chart vertex or a fixed
 * corner and the scaffold adds no unknowns). Its triangles at odd depth lie inside the box
 * and outside every chart (holes included). The start is accepted as overlap-free only
 * when the charts' triangles keep one orientation per chart and, with the scaffold, tile
 * the box exactly (areas sum to the box's within 1e-7): anything else overlaps somewhere.
 * Re-meshing is a fresh triangulation at the current positions (Jiang et al. re-mesh
 * where scaffold triangles degrade; re-building it all is simpler and costs one
 * triangulation per round, small next to a stage-2 round). */
#include "scaffold.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sort_keys.h"
#include "triangulate.h"
#include "vec2.h"

#define DEFAULT_WEIGHT 0.01
#define DEFAULT_REMESH 10
#define BOX_MARGIN 1.0        /* box side = (1 + 2 margin) x the charts' extent */
#define TILING_TOLERANCE 1e-7 /* relative area mismatch that means overlap */

typedef struct scaffold_build {
    size_t base;      /* first extra vertex index: the mesh's vertex count */
    double *position; /* box corners, 2 each */
    size_t vertex_count, vertex_cap;
    uint32_t *triangle;
    double *rest;
    size_t triangle_count, triangle_cap, rest_cap;
    size_t scaffolded, skipped;
    uint8_t *skipped_chart; /* per chart when not NULL (a box per chart): 1 when skipped */
} scaffold_build;

static int compare_u32(const void *pa, const void *pb)
{
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return a < b ? -1 : a > b;
}

/* Whether every chart of the component keeps one orientation (no fold, no mirrored part). */
static int one_orientation_per_chart(const texopt_mesh *mesh, const double *x, const uint32_t *tris, size_t n,
                                     int8_t *sign)
{
    int ok = 1;
    for (size_t k = 0; k < n; k++) {
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[k];
        double a = texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]);
        int8_t s = a > 0.0 ? 1 : a < 0.0 ? -1 : 0;
        int8_t *cs = &sign[mesh->chart_of[tris[k]]];
        if (s != 0 && *cs != 0 && s != *cs)
            ok = 0;
        if (*cs == 0)
            *cs = s;
    }
    for (size_t k = 0; k < n; k++)
        sign[mesh->chart_of[tris[k]]] = 0;
    return ok;
}

/* Boundary edges (used by one triangle of the component) as sorted vertex pairs into
 * *edges; -1 when some edge has more than two triangles, or out of memory. */
static long boundary_edges(const texopt_mesh *mesh, const uint32_t *tris, size_t n, uint64_t **edges)
{
    uint64_t *keys = malloc((3 * n + 1) * sizeof *keys);
    if (!keys)
        return -1;
    for (size_t k = 0; k < n; k++)
        for (int j = 0; j < 3; j++) {
            uint32_t a = mesh->triangle[3 * (size_t)tris[k] + j], b = mesh->triangle[3 * (size_t)tris[k] + (j + 1) % 3];
            keys[3 * k + j] = texopt_edge_key(a, b);
        }
    qsort(keys, 3 * n, sizeof *keys, texopt_compare_u64);
    size_t out = 0;
    for (size_t i = 0; i < 3 * n;) {
        size_t j = i;
        while (j < 3 * n && keys[j] == keys[i])
            j++;
        if (j - i > 2) {
            free(keys);
            return -1;
        }
        if (j - i == 1)
            keys[out++] = keys[i];
        i = j;
    }
    *edges = keys;
    return (long)out;
}

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 0;
    size_t c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void *q = realloc(*p, c * size);
    if (!q)
        return -1;
    *p = q;
    *cap = c;
    return 0;
}

/* The box around the component's vertices (or `fixed`, x0 y0 x1 y1, when not NULL),
 * counter-clockwise from its lowest corner. */
static void component_box(const texopt_mesh *mesh, const double *x, const uint32_t *tris, size_t n, const double *fixed,
                          double box[8])
{
    if (fixed) {
        double c[8] = {fixed[0], fixed[1], fixed[2], fixed[1], fixed[2], fixed[3], fixed[0], fixed[3]};
        memcpy(box, c, sizeof c);
        return;
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t k = 0; k < n; k++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 2; a++) {
                double c = x[2 * (size_t)mesh->triangle[3 * (size_t)tris[k] + j] + a];
                lo[a] = fmin(lo[a], c);
                hi[a] = fmax(hi[a], c);
            }
    double m = BOX_MARGIN * fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1.0);
    double x0 = lo[0] - m, y0 = lo[1] - m, x1 = hi[0] + m, y1 = hi[1] + m;
    double c[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    memcpy(box, c, sizeof c);
}

/* Appends the scaffold triangles (odd depth) of a triangulation whose points are the
 * component's boundary vertices `vert` (nb of them) then the 4 box corners, when they
 * tile the box with the charts; returns 1 when appended, 0 when the start overlaps, -1
 * when out of memory. */
static int append_scaffold(scaffold_build *sb, const texopt_triangulation *tr, const double *pts, const uint32_t *vert,
                           size_t nb, double chart_area, double box_area)
{
    double area = chart_area;
    size_t count = 0;
    for (size_t t = 0; t < tr->triangle_count; t++)
        if (tr->depth[t] % 2 == 1) {
            const uint32_t *v = tr->triangle + 3 * t;
            area += texopt_signed_area(pts + 2 * (size_t)v[0], pts + 2 * (size_t)v[1], pts + 2 * (size_t)v[2]);
            count++;
        }
    if (!(fabs(area - box_area) <= TILING_TOLERANCE * box_area))
        return 0;
    if (grow((void **)&sb->triangle, &sb->triangle_cap, sb->triangle_count + count, 3 * sizeof *sb->triangle) ||
        grow((void **)&sb->rest, &sb->rest_cap, sb->triangle_count + count, 6 * sizeof *sb->rest) ||
        grow((void **)&sb->position, &sb->vertex_cap, sb->vertex_count + 4, 2 * sizeof *sb->position))
        return -1;
    for (size_t t = 0; t < tr->triangle_count; t++) {
        if (tr->depth[t] % 2 != 1)
            continue;
        for (int j = 0; j < 3; j++) {
            uint32_t p = tr->triangle[3 * t + j];
            sb->triangle[3 * sb->triangle_count + j] =
                p < nb ? vert[p] : (uint32_t)(sb->base + sb->vertex_count + (p - nb));
            sb->rest[6 * sb->triangle_count + 2 * j] = pts[2 * (size_t)p];
            sb->rest[6 * sb->triangle_count + 2 * j + 1] = pts[2 * (size_t)p + 1];
        }
        sb->triangle_count++;
    }
    memcpy(sb->position + 2 * sb->vertex_count, pts + 2 * nb, 8 * sizeof *pts);
    sb->vertex_count += 4;
    return 1;
}

/* Scaffolds one box around the triangles tris (n of them); 0 when its start overlaps (or
 * cannot be triangulated), 1 when scaffolded, -1 out of memory. */
static int scaffold_component(scaffold_build *sb, const texopt_mesh *mesh, const double *x, const uint32_t *tris,
                              size_t n, const double *fixed_box, int8_t *sign)
{
    if (n == 0 || !one_orientation_per_chart(mesh, x, tris, n, sign))
        return 0;
    uint64_t *edges = NULL;
    long ne = boundary_edges(mesh, tris, n, &edges);
    if (ne <= 0) { /* a non-manifold edge, or a closed surface without boundary */
        free(edges);
        return 0;
    }
    uint32_t *vert = malloc(2 * (size_t)ne * sizeof *vert);
    double *pts = malloc((4 * (size_t)ne + 8) * sizeof *pts);
    uint32_t *seg = malloc((4 * (size_t)ne + 8) * sizeof *seg);
    int result = -1;
    if (!vert || !pts || !seg)
        goto done;
    for (long e = 0; e < ne; e++) {
        vert[2 * e] = (uint32_t)(edges[e] >> 32);
        vert[2 * e + 1] = (uint32_t)edges[e];
    }
    qsort(vert, 2 * (size_t)ne, sizeof *vert, compare_u32);
    size_t nb = 0;
    for (size_t i = 0; i < 2 * (size_t)ne; i++)
        if (nb == 0 || vert[i] != vert[nb - 1])
            vert[nb++] = vert[i];
    for (size_t i = 0; i < nb; i++)
        memcpy(pts + 2 * i, x + 2 * (size_t)vert[i], 2 * sizeof *pts);
    component_box(mesh, x, tris, n, fixed_box, pts + 2 * nb);
    for (long e = 0; e < ne; e++) {
        uint32_t a = (uint32_t)(edges[e] >> 32), b = (uint32_t)edges[e];
        seg[2 * e] = (uint32_t)((uint32_t *)bsearch(&a, vert, nb, sizeof *vert, compare_u32) - vert);
        seg[2 * e + 1] = (uint32_t)((uint32_t *)bsearch(&b, vert, nb, sizeof *vert, compare_u32) - vert);
    }
    for (int k = 0; k < 4; k++) {
        seg[2 * ne + 2 * k] = (uint32_t)(nb + k);
        seg[2 * ne + 2 * k + 1] = (uint32_t)(nb + (k + 1) % 4);
    }
    double chart_area = 0.0;
    for (size_t k = 0; k < n; k++) {
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[k];
        chart_area += fabs(texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]));
    }
    const double *c = pts + 2 * nb;
    double box_area = (c[2] - c[0]) * (c[5] - c[3]);
    texopt_triangulation tr;
    char ignored[128];
    result = 0; /* coincident boundary vertices or crossing boundaries: the start overlaps */
    texopt_status st = texopt_triangulate(pts, nb + 4, seg, (size_t)ne + 4, &tr, ignored, sizeof ignored);
    if (st == TEXOPT_OK) {
        result = append_scaffold(sb, &tr, pts, vert, nb, chart_area, box_area);
        texopt_triangulation_destroy(&tr);
    } else if (st == TEXOPT_E_NOMEM)
        result = -1;
done:
    free(edges);
    free(vert);
    free(pts);
    free(seg);
    return result;
}

/* Whether the chart's triangles tris hold both orientations and no fold-over: mirrored
 * halves welded at their mirror line (mesh.h), each of which can be boxed on its own. */
static int clean_mirror(const texopt_mesh *mesh, const double *x, const uint32_t *tris, size_t n)
{
    int positive = 0, negative = 0;
    for (size_t k = 0; k < n; k++) {
        if (mesh->flags[tris[k]] & TEXOPT_TRI_FLIPPED)
            return 0;
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[k];
        double a = texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]);
        positive |= a > 0.0;
        negative |= a < 0.0;
    }
    return positive && negative;
}

/* A clean mirror scaffolded as two components, one per orientation: the halves lie on one
 * another by design (the budget pays their texels once), and each half's own box keeps it
 * off itself. Triangles without area belong to neither half: those joining the halves at
 * their mirror line have two corners on one point (one vertex of each half, which stage 2
 * solves as one unknown, meshwise.h), so they keep no area and, in a half's box, would put
 * two boundary vertices on one point, which no triangulation tiles. 1 when both are
 * scaffolded, 0 when one is not, -1 out of memory. */
static int scaffold_halves(scaffold_build *sb, const texopt_mesh *mesh, const double *x, const uint32_t *tris, size_t n,
                           int8_t *sign)
{
    uint32_t *half = malloc(n * sizeof *half);
    if (!half)
        return -1;
    size_t positive = 0, negative = n;
    for (size_t k = 0; k < n; k++) {
        const uint32_t *v = mesh->triangle + 3 * (size_t)tris[k];
        double a = texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]);
        if (a > 0.0)
            half[positive++] = tris[k];
        else if (a < 0.0)
            half[--negative] = tris[k];
    }
    int first = scaffold_component(sb, mesh, x, half, positive, NULL, sign);
    int second = first < 0 ? -1 : scaffold_component(sb, mesh, x, half + negative, n - negative, NULL, sign);
    free(half);
    return first < 0 || second < 0 ? -1 : first && second;
}

static void scaffold_build_free(scaffold_build *sb)
{
    free(sb->position);
    free(sb->triangle);
    free(sb->rest);
    memset(sb, 0, sizeof *sb);
}

/* Scaffolds every box at positions x: one per chart, or one for all (one_box), that one
 * fixed_box when not NULL and without the charts marked in unboxed (may be NULL). */
static texopt_status build_scaffold(const texopt_mesh *mesh, const double *x, int one_box, const double *fixed_box,
                                    const uint8_t *unboxed, scaffold_build *sb, char *err, size_t err_len)
{
    size_t nc = mesh->chart_count, nt = mesh->triangle_count;
    uint32_t *start = calloc(nc + 2, sizeof *start), *order = malloc((nt ? nt : 1) * sizeof *order);
    int8_t *sign = calloc(nc ? nc : 1, 1);
    int failed = !start || !order || !sign;
    for (size_t t = 0; t < nt && !failed; t++)
        start[mesh->chart_of[t] + 1]++;
    for (size_t c = 0; c < nc && !failed; c++)
        start[c + 1] += start[c];
    for (size_t t = 0; t < nt && !failed; t++)
        order[start[mesh->chart_of[t]]++] = (uint32_t)t;
    for (size_t c = nc; c > 0 && !failed; c--)
        start[c] = start[c - 1];
    if (!failed)
        start[0] = 0;
    size_t boxes = one_box ? 1 : nc, boxed_triangles = nt, boxed_charts = nc;
    if (one_box && unboxed && !failed) {
        boxed_triangles = boxed_charts = 0;
        for (size_t k = 0; k < nt; k++)
            if (!unboxed[mesh->chart_of[order[k]]])
                order[boxed_triangles++] = order[k];
        for (size_t c = 0; c < nc; c++)
            boxed_charts += !unboxed[c];
    }
    for (size_t c = 0; c < boxes && !failed; c++) {
        size_t first = one_box ? 0 : start[c], last = one_box ? boxed_triangles : start[c + 1];
        size_t charts = one_box ? boxed_charts : 1;
        int r = !one_box && clean_mirror(mesh, x, order + first, last - first)
                    ? scaffold_halves(sb, mesh, x, order + first, last - first, sign)
                    : scaffold_component(sb, mesh, x, order + first, last - first, one_box ? fixed_box : NULL, sign);
        failed = r < 0;
        if (r > 0)
            sb->scaffolded += charts;
        else
            sb->skipped += charts;
        if (sb->skipped_chart && !one_box)
            sb->skipped_chart[c] = r == 0;
    }
    free(start);
    free(order);
    free(sign);
    return failed ? texopt_fail(err, err_len, TEXOPT_E_NOMEM, "scaffold: out of memory") : TEXOPT_OK;
}

texopt_status texopt_scaffold_overlapping_charts(const texopt_mesh *mesh, const double *texel, uint8_t *overlapping,
                                                 size_t *count, char *err, size_t err_len)
{
    if (!mesh || !texel || !overlapping || (mesh->triangle_count && (!mesh->triangle || !mesh->chart_of)))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "scaffold: NULL mesh, layout or output");
    scaffold_build sb = {0};
    sb.base = mesh->vertex_count;
    sb.skipped_chart = overlapping;
    memset(overlapping, 0, mesh->chart_count);
    texopt_status st = build_scaffold(mesh, texel, 0, NULL, NULL, &sb, err, err_len);
    if (count)
        *count = sb.skipped;
    scaffold_build_free(&sb);
    return st;
}

/* Maps a round's stage-2 progress into the whole solve's, so it never goes back. */
typedef struct round_monitor {
    const texopt_monitor *outer;
    double offset, scale;
} round_monitor;

static void forward_round(void *user, const texopt_progress *p)
{
    const round_monitor *rm = user;
    texopt_progress q = *p;
    q.stage_fraction = rm->offset + rm->scale * p->stage_fraction;
    q.fraction = q.stage_fraction;
    texopt_monitor_report(rm->outer, &q);
}

static void add_round(texopt_scaffold_report *total, const texopt_meshwise_report *r)
{
    int iterations = total->meshwise.iterations + r->iterations;
    double seconds = total->meshwise.seconds + r->seconds, initial = total->meshwise.energy_initial;
    int first = total->rounds == 1;
    total->meshwise = *r;
    total->meshwise.iterations = iterations;
    total->meshwise.seconds = seconds;
    if (!first)
        total->meshwise.energy_initial = initial;
}

texopt_status texopt_scaffold_solve(const texopt_mesh *mesh, const texopt_triangle_target *targets,
                                    const double *initial_texel, const texopt_meshwise_options *opt,
                                    const texopt_scaffold_options *sopt, double *texel_out,
                                    texopt_scaffold_report *report, const texopt_monitor *monitor, char *err,
                                    size_t err_len)
{
    if (!mesh || !targets || !texel_out || !mesh->texel ||
        (mesh->triangle_count && (!mesh->triangle || !mesh->chart_of)))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "scaffold: NULL mesh, targets or output");
    if (sopt && (sopt->weight < 0.0 || !isfinite(sopt->weight) || sopt->remesh_iterations < 0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "scaffold: negative weight or re-mesh interval");
    texopt_meshwise_options mopt = {0};
    if (opt)
        mopt = *opt;
    int max_iterations = mopt.max_iterations > 0 ? mopt.max_iterations : 50;
    int round = sopt && sopt->remesh_iterations > 0 ? sopt->remesh_iterations : DEFAULT_REMESH;
    size_t n = 2 * mesh->vertex_count;
    double *x = malloc((n ? n : 1) * sizeof *x), *next = malloc((n ? n : 1) * sizeof *next);
    if (!x || !next) {
        free(x);
        free(next);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "scaffold: out of memory");
    }
    memcpy(x, initial_texel ? initial_texel : mesh->texel, n * sizeof *x);
    texopt_scaffold_report total;
    memset(&total, 0, sizeof total);
    texopt_status st = TEXOPT_OK;
    round_monitor rm = {monitor, 0.0, 0.0};
    texopt_monitor inner = {forward_round, &rm, monitor ? monitor->cancel : NULL};
    for (int done = 0; st == TEXOPT_OK && done < max_iterations;) {
        scaffold_build sb = {0};
        sb.base = mesh->vertex_count;
        st = build_scaffold(mesh, x, sopt && sopt->one_box, sopt ? sopt->box : NULL, sopt ? sopt->unboxed : NULL, &sb,
                            err, err_len);
        texopt_meshwise_scaffold sc = {sb.vertex_count,   sb.position,
                                       sb.triangle_count, sb.triangle,
                                       sb.rest,           sopt && sopt->weight > 0.0 ? sopt->weight : DEFAULT_WEIGHT};
        mopt.scaffold = sb.triangle_count ? &sc : NULL;
        mopt.max_iterations = max_iterations - done < round ? max_iterations - done : round;
        texopt_meshwise_report r;
        rm.offset = (double)done / max_iterations;
        rm.scale = (double)mopt.max_iterations / max_iterations;
        if (st == TEXOPT_OK)
            st = texopt_meshwise_solve(mesh, targets, x, &mopt, next, &r, &inner, err, err_len);
        if (st == TEXOPT_OK) {
            memcpy(x, next, n * sizeof *x);
            total.rounds++;
            total.charts_scaffolded = sb.scaffolded;
            total.charts_skipped = sb.skipped;
            total.triangles = sb.triangle_count;
            add_round(&total, &r);
            mopt.barrier_weight = r.barrier_weight_final;
            done += r.iterations;
            if (r.iterations < mopt.max_iterations)
                done = max_iterations; /* converged */
        }
        scaffold_build_free(&sb);
    }
    if (st == TEXOPT_OK) {
        memcpy(texel_out, x, n * sizeof *x);
        if (report)
            *report = total;
    }
    free(x);
    free(next);
    return st;
}

/* Marks the texel centres strictly inside triangle t; owner[] holds, per centre, the
 * first chart and orientation to cover it (2 chart + (counter-clockwise) + 1), and flags
 * bit 0 / bit 1 a second cover from the same chart and orientation / another chart. */
static void cover_triangle(const texopt_mesh *mesh, const double *texel, size_t t, const double lo[2], size_t w,
                           size_t h, uint32_t *owner, uint8_t *flags)
{
    const uint32_t *v = mesh->triangle + 3 * t;
    const double *a = texel + 2 * (size_t)v[0], *b = texel + 2 * (size_t)v[1], *c = texel + 2 * (size_t)v[2];
    double s = texopt_signed_area(a, b, c);
    if (!(fabs(s) > 0.0))
        return;
    double x0 = fmin(a[0], fmin(b[0], c[0])) - lo[0], x1 = fmax(a[0], fmax(b[0], c[0])) - lo[0];
    double y0 = fmin(a[1], fmin(b[1], c[1])) - lo[1], y1 = fmax(a[1], fmax(b[1], c[1])) - lo[1];
    size_t i0 = (size_t)fmax(0.0, floor(x0 - 0.5)), i1 = (size_t)fmin((double)w - 1, ceil(x1));
    size_t j0 = (size_t)fmax(0.0, floor(y0 - 0.5)), j1 = (size_t)fmin((double)h - 1, ceil(y1));
    uint32_t code = 2 * mesh->chart_of[t] + (s > 0.0) + 1;
    for (size_t j = j0; j <= j1; j++)
        for (size_t i = i0; i <= i1; i++) {
            double p[2] = {lo[0] + (double)i + 0.5, lo[1] + (double)j + 0.5};
            double e0 = texopt_signed_area(a, b, p), e1 = texopt_signed_area(b, c, p), e2 = texopt_signed_area(c, a, p);
            int inside = s > 0.0 ? (e0 > 0.0 && e1 > 0.0 && e2 > 0.0) : (e0 < 0.0 && e1 < 0.0 && e2 < 0.0);
            if (!inside)
                continue;
            size_t k = j * w + i;
            if (owner[k] == 0)
                owner[k] = code;
            else if (owner[k] == code)
                flags[k] |= 1;
            else if ((owner[k] - 1) / 2 != (code - 1) / 2)
                flags[k] |= 2;
        }
}

/* texopt_count_overlap, and per chart (when not NULL) its centres covered twice. */
static texopt_status count_overlap(const texopt_mesh *mesh, const double *texel, size_t *within, size_t *between,
                                   size_t *chart_within, char *err, size_t err_len)
{
    if (!mesh || !texel || !within || !between)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "overlap count: NULL argument");
    if (chart_within)
        memset(chart_within, 0, mesh->chart_count * sizeof *chart_within);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t v = 0; v < mesh->vertex_count; v++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], floor(texel[2 * v + a]));
            hi[a] = fmax(hi[a], ceil(texel[2 * v + a]));
        }
    *within = *between = 0;
    if (mesh->vertex_count == 0)
        return TEXOPT_OK;
    double w = hi[0] - lo[0] + 1, h = hi[1] - lo[1] + 1;
    if (!(w * h <= 67108864.0))
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "overlap count: layout spans %g x %g texels", w, h);
    uint32_t *owner = calloc((size_t)(w * h), sizeof *owner);
    uint8_t *flags = calloc((size_t)(w * h), 1);
    if (!owner || !flags) {
        free(owner);
        free(flags);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "overlap count: out of memory");
    }
    for (size_t t = 0; t < mesh->triangle_count; t++)
        cover_triangle(mesh, texel, t, lo, (size_t)w, (size_t)h, owner, flags);
    for (size_t k = 0; k < (size_t)(w * h); k++) {
        *within += flags[k] & 1;
        *between += (flags[k] >> 1) & 1;
        if (chart_within && (flags[k] & 1))
            chart_within[(owner[k] - 1) / 2]++;
    }
    free(owner);
    free(flags);
    return TEXOPT_OK;
}

texopt_status texopt_count_overlap(const texopt_mesh *mesh, const double *texel, size_t *within, size_t *between,
                                   char *err, size_t err_len)
{
    return count_overlap(mesh, texel, within, between, NULL, err, err_len);
}

texopt_status texopt_count_overlap_per_chart(const texopt_mesh *mesh, const double *texel, size_t *chart_within,
                                             char *err, size_t err_len)
{
    size_t within, between;
    if (!chart_within)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "overlap count: NULL argument");
    return count_overlap(mesh, texel, &within, &between, chart_within, err, err_len);
}
