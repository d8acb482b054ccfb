/* gap_layer.c - a thin layer of triangles around each chart; see gap_layer.h. */
#include "gap_layer.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "chart_gap.h"
#include "vec2.h"

#define NONE UINT32_MAX

/* Unit outward normal of boundary edge e in layout x (its triangle's orientation there says
 * which side is out) and its length; 0 when the edge or its triangle has no size. */
static int outward_normal(const texopt_mesh *mesh, const double *x, const texopt_boundary_edge *e, double n[2],
                          double *len)
{
    const uint32_t *v = mesh->triangle + 3 * (size_t)e->triangle;
    double s = texopt_signed_area(x + 2 * (size_t)v[0], x + 2 * (size_t)v[1], x + 2 * (size_t)v[2]);
    const double *a = x + 2 * (size_t)e->from, *b = x + 2 * (size_t)e->to;
    double dx = b[0] - a[0], dy = b[1] - a[1];
    *len = hypot(dx, dy);
    if (!(*len > 0.0) || s == 0.0)
        return 0;
    n[0] = (s > 0.0 ? dy : -dy) / *len;
    n[1] = (s > 0.0 ? -dx : dx) / *len;
    return 1;
}

/* The layer vertex of boundary vertex v (edges in, out) in layout x: v moved out by the
 * width scaled as the adjacent edges are from the start to x; 0 on a spike. */
static int layer_vertex(const texopt_mesh *mesh, const double *x, const double *start, const texopt_boundary_edge *in,
                        const texopt_boundary_edge *out, uint32_t v, double width, double *p)
{
    double n_in[2], n_out[2], l_in, l_out, s_in, s_out, ignored[2];
    if (!outward_normal(mesh, x, in, n_in, &l_in) || !outward_normal(mesh, x, out, n_out, &l_out) ||
        !outward_normal(mesh, start, in, ignored, &s_in) || !outward_normal(mesh, start, out, ignored, &s_out))
        return 0;
    double m[2] = {n_in[0] + n_out[0], n_in[1] + n_out[1]}, len = hypot(m[0], m[1]);
    if (!(len > 1e-6))
        return 0;
    double d = width * (l_in + l_out) / (s_in + s_out);
    p[0] = x[2 * (size_t)v] + d * m[0] / len;
    p[1] = x[2 * (size_t)v + 1] + d * m[1] / len;
    return 1;
}

void texopt_gap_layer_destroy(texopt_gap_layer *g)
{
    free(g->mesh.texel);
    free(g->mesh.triangle);
    free(g->mesh.area_texel);
    free(g->mesh.flags);
    free(g->mesh.chart_of);
    free(g->mesh.chart_sign);
    free(g->start);
    free(g->reference);
    memset(g, 0, sizeof *g);
}

/* Per vertex, its incoming and outgoing boundary edge (indices into e, NONE when none);
 * per chart, 1 in bad when a vertex has more than one of either. */
static void link_edges(const texopt_mesh *mesh, const texopt_boundary_edge *e, size_t ne, uint32_t *in, uint32_t *out,
                       uint8_t *bad)
{
    for (size_t i = 0; i < ne; i++) {
        uint8_t *b = &bad[mesh->chart_of[e[i].triangle]];
        *b |= out[e[i].from] != NONE || in[e[i].to] != NONE;
        out[e[i].from] = in[e[i].to] = (uint32_t)i;
    }
}

/* Fills g's three layouts at layer vertex `at` of boundary vertex v; 0 on a spike. */
static int place_layer_vertex(const texopt_mesh *mesh, const double *reference, const double *start,
                              const texopt_boundary_edge *in, const texopt_boundary_edge *out, uint32_t v, double width,
                              texopt_gap_layer *g, size_t at)
{
    return layer_vertex(mesh, mesh->texel, start, in, out, v, width, g->mesh.texel + 2 * at) &&
           layer_vertex(mesh, start, start, in, out, v, width, g->start + 2 * at) &&
           layer_vertex(mesh, reference, start, in, out, v, width, g->reference + 2 * at);
}

/* The layer of every chart not in bad (which gets the charts found bad on the way). */
static texopt_status build(const texopt_mesh *mesh, const double *reference, const double *start, double width,
                           uint8_t *bad, texopt_gap_layer *g, char *err, size_t err_len)
{
    memset(g, 0, sizeof *g);
    texopt_boundary_edge *e = NULL;
    size_t nb = texopt_boundary_edges(mesh, &e);
    size_t nv = mesh->vertex_count, nt = mesh->triangle_count, nc = mesh->chart_count;
    uint32_t *in = malloc((nv ? nv : 1) * sizeof *in), *out = malloc((nv ? nv : 1) * sizeof *out);
    uint32_t *layer_of = malloc((nv ? nv : 1) * sizeof *layer_of);
    texopt_mesh *m = &g->mesh;
    size_t cap_v = nv + nb, cap_t = nt + 2 * nb;
    m->texel = malloc(2 * (cap_v ? cap_v : 1) * sizeof *m->texel);
    g->start = malloc(2 * (cap_v ? cap_v : 1) * sizeof *g->start);
    g->reference = malloc(2 * (cap_v ? cap_v : 1) * sizeof *g->reference);
    m->triangle = malloc(3 * (cap_t ? cap_t : 1) * sizeof *m->triangle);
    m->area_texel = malloc((cap_t ? cap_t : 1) * sizeof *m->area_texel);
    m->flags = calloc(cap_t ? cap_t : 1, sizeof *m->flags);
    m->chart_of = malloc((cap_t ? cap_t : 1) * sizeof *m->chart_of);
    m->chart_sign = malloc((nc ? nc : 1) * sizeof *m->chart_sign);
    texopt_status st = TEXOPT_OK;
    if (!e || !in || !out || !layer_of || !m->texel || !g->start || !g->reference || !m->triangle || !m->area_texel ||
        !m->flags || !m->chart_of || !m->chart_sign)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "gap layer: no memory");
    if (st == TEXOPT_OK) {
        m->width = mesh->width;
        m->height = mesh->height;
        m->chart_count = nc;
        if (mesh->chart_sign)
            memcpy(m->chart_sign, mesh->chart_sign, nc * sizeof *m->chart_sign);
        else { /* a mesh without it (made by hand) gives none */
            free(m->chart_sign);
            m->chart_sign = NULL;
        }
        memcpy(m->texel, mesh->texel, 2 * nv * sizeof *m->texel);
        memcpy(g->start, start, 2 * nv * sizeof *g->start);
        memcpy(g->reference, reference, 2 * nv * sizeof *g->reference);
        memcpy(m->triangle, mesh->triangle, 3 * nt * sizeof *m->triangle);
        memcpy(m->area_texel, mesh->area_texel, nt * sizeof *m->area_texel);
        memcpy(m->flags, mesh->flags, nt * sizeof *m->flags);
        memcpy(m->chart_of, mesh->chart_of, nt * sizeof *m->chart_of);
        for (size_t v = 0; v < nv; v++)
            in[v] = out[v] = layer_of[v] = NONE;
        link_edges(mesh, e, nb, in, out, bad);
        for (size_t i = 0; i < nb; i++) { /* first the bad charts, placing into one slot ... */
            uint32_t v = e[i].from;
            if (in[v] == NONE || !place_layer_vertex(mesh, reference, start, &e[in[v]], &e[i], v, width, g, nv))
                bad[mesh->chart_of[e[i].triangle]] = 1;
        }
        size_t at = nv; /* ... then the good ones' layer vertices, none without a triangle */
        for (size_t i = 0; i < nb; i++)
            if (!bad[mesh->chart_of[e[i].triangle]]) {
                place_layer_vertex(mesh, reference, start, &e[in[e[i].from]], &e[i], e[i].from, width, g, at);
                layer_of[e[i].from] = (uint32_t)at++;
            }
        m->vertex_count = at;
        size_t t = nt;
        for (size_t i = 0; i < nb; i++) {
            uint32_t a = e[i].from, b = e[i].to, c = mesh->chart_of[e[i].triangle];
            if (bad[c] || layer_of[a] == NONE || layer_of[b] == NONE)
                continue;
            uint32_t quad[6] = {b, a, layer_of[a], b, layer_of[a], layer_of[b]};
            for (int k = 0; k < 2; k++, t++) {
                memcpy(m->triangle + 3 * t, quad + 3 * k, 3 * sizeof *quad);
                const uint32_t *v = m->triangle + 3 * t;
                m->area_texel[t] = texopt_signed_area(m->texel + 2 * (size_t)v[0], m->texel + 2 * (size_t)v[1],
                                                      m->texel + 2 * (size_t)v[2]);
                m->chart_of[t] = c;
            }
        }
        m->triangle_count = t;
        for (size_t c = 0; c < nc; c++) {
            g->charts_without += bad[c] != 0;
            g->charts_layered += bad[c] == 0;
        }
    }
    free(e);
    free(in);
    free(out);
    free(layer_of);
    if (st != TEXOPT_OK)
        texopt_gap_layer_destroy(g);
    return st;
}

/* Marks in bad the charts with a layer triangle that collapses in one of the three layouts
 * or turns between them (at a concave corner sharper than the width allows); their count. */
static size_t mark_turned_layers(const texopt_mesh *mesh, const texopt_gap_layer *g, uint8_t *bad)
{
    size_t marked = 0;
    const double *frames[3] = {g->mesh.texel, g->start, g->reference};
    for (size_t t = mesh->triangle_count; t < g->mesh.triangle_count; t++) {
        const uint32_t *v = g->mesh.triangle + 3 * t;
        int sign[3], turned = 0;
        for (int f = 0; f < 3; f++) {
            const double *a = frames[f] + 2 * (size_t)v[0], *b = frames[f] + 2 * (size_t)v[1],
                         *c = frames[f] + 2 * (size_t)v[2];
            sign[f] = texopt_signed_area(a, b, c) > 0.0 ? 1 : -1;
            turned |= texopt_texel_triangle_degenerate(a, b, c) || sign[f] != sign[0];
        }
        uint32_t c = g->mesh.chart_of[t];
        marked += turned && !bad[c];
        bad[c] |= (uint8_t)turned;
    }
    return marked;
}

texopt_status texopt_gap_layer_create(const texopt_mesh *mesh, const double *reference, const double *start,
                                      double width, texopt_gap_layer *g, char *err, size_t err_len)
{
    uint8_t *bad = calloc(mesh->chart_count ? mesh->chart_count : 1, 1);
    if (!bad) {
        memset(g, 0, sizeof *g);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "gap layer: no memory");
    }
    texopt_status st = build(mesh, reference, start, width, bad, g, err, err_len);
    if (st == TEXOPT_OK && mark_turned_layers(mesh, g, bad) > 0) { /* the others' layers are the same again */
        texopt_gap_layer_destroy(g);
        st = build(mesh, reference, start, width, bad, g, err, err_len);
    }
    free(bad);
    return st;
}
