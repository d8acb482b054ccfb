/* mesh.c - welded connectivity, charts, areas and flags of one texture domain (mesh.h).
 *
 * The structure the method of Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen", works on: its per-triangle stage renders a triangle's one-ring
 * through UV seams (3D points), its mesh-wise stage moves UV vertices chart by chart, and
 * its cost is measured in texels. Welding uses exact float equality through hash maps;
 * charts come from union-find over shared UV vertices.
 *
 * Does not: measure texel coverage or overlaps (coverage.c), repair meshes, merge nearly
 * equal vertices, or decide anything about materials (model.c). */
#include "mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vec2.h"
#include "vec3.h"

/* Relative degeneracy threshold: doubled area <= this * (longest edge)^2. Floats carry
 * ~6e-8 relative precision, so a triangle this thin has no reliable shape in either space. */
#define DEGENERATE_RELATIVE 1e-10
/* A UV counts as wrapped when it leaves [0,1] by more than this many texels: exporters write
 * values like -1e-7 that rely on no wrap mode. */
#define WRAP_TOLERANCE_TEXELS 1e-3
/* A reversed orientation patch smaller than this share of its chart's area is a fold-over
 * (FLIPPED); a larger one is a mirrored part of the chart. Fold-overs from bad unwraps are a
 * few triangles; mirrored halves welded at the mirror line are about half their chart. */
#define FOLD_PATCH_FRACTION 0.2

/* ---- exact-equality hash map over float tuples ---------------------------------------- */

/* Open addressing over indices into a float array of `width` floats per key; slot holds
 * index + 1, 0 is empty. -0 and +0 hash alike (they compare equal). */
typedef struct weld_map {
    uint32_t *slot;
    size_t mask;
    const float *keys;
    int width;
} weld_map;

static uint64_t float_bits(float f)
{
    if (f == 0.0f)
        return 0;
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

static uint64_t hash_key(const float *k, int width)
{
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int i = 0; i < width; i++) {
        h ^= float_bits(k[i]) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xbf58476d1ce4e5b9ull;
        h ^= h >> 31;
    }
    return h;
}

static int keys_equal(const float *a, const float *b, int width)
{
    for (int i = 0; i < width; i++)
        if (a[i] != b[i])
            return 0;
    return 1;
}

static int weld_map_init(weld_map *map, size_t count, const float *keys, int width)
{
    size_t cap = 16;
    while (cap < 2 * count)
        cap *= 2;
    map->slot = calloc(cap, sizeof *map->slot);
    map->mask = cap - 1;
    map->keys = keys;
    map->width = width;
    return map->slot ? 0 : -1;
}

/* Returns the first index inserted with a key equal to that of `index`, inserting `index`
 * when there is none. */
static uint32_t weld_map_find_or_insert(weld_map *map, uint32_t index)
{
    const float *key = map->keys + (size_t)index * (size_t)map->width;
    size_t i = (size_t)hash_key(key, map->width) & map->mask;
    for (;;) {
        uint32_t s = map->slot[i];
        if (s == 0) {
            map->slot[i] = index + 1;
            return index;
        }
        if (keys_equal(map->keys + (size_t)(s - 1) * (size_t)map->width, key, map->width))
            return s - 1;
        i = (i + 1) & map->mask;
    }
}

/* ---- union-find ------------------------------------------------------------------------ */

static uint32_t uf_find(uint32_t *parent, uint32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

/* ---- building steps ---------------------------------------------------------------------- */

/* The domain's model vertices in primitive order, each as 5 floats (x, y, z, u, v) so the
 * UV weld and the point weld read one array. Checks ranges and finiteness on the way. */
static texopt_status gather_vertices(const texopt_model *model, const texopt_domain *dom, float **keys_out,
                                     size_t *count_out, char *err, size_t err_len)
{
    size_t count = 0;
    for (int k = 0; k < dom->primitive_count; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        if (prim->first_vertex > model->vertex_count || prim->vertex_count > model->vertex_count - prim->first_vertex)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "primitive %d: vertices [%zu, +%zu) past the model's %zu", dom->primitives[k],
                               prim->first_vertex, prim->vertex_count, model->vertex_count);
        count += prim->vertex_count;
    }
    if (count >= UINT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "domain has %zu vertices (limit %u)", count,
                           (unsigned)UINT32_MAX - 1);
    float *keys = malloc(sizeof(float) * 5 * (count > 0 ? count : 1));
    if (!keys)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu vertices", count);
    size_t n = 0;
    for (int k = 0; k < dom->primitive_count; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        for (size_t i = 0; i < prim->vertex_count; i++, n++) {
            size_t mv = prim->first_vertex + i;
            float *key = keys + 5 * n;
            memcpy(key, model->positions + 3 * mv, 3 * sizeof(float));
            memcpy(key + 3, model->uvs + 2 * mv, 2 * sizeof(float));
            for (int c = 0; c < 5; c++)
                if (!isfinite(key[c])) {
                    free(keys);
                    return texopt_fail(err, err_len, TEXOPT_E_MALFORMED, "primitive %d: vertex %zu has a non-finite %s",
                                       dom->primitives[k], i, c < 3 ? "position" : "UV");
                }
        }
    }
    *keys_out = keys;
    *count_out = count;
    return TEXOPT_OK;
}

/* UV vertices: local model vertices with equal (position, uv). */
static texopt_status weld_uv_vertices(texopt_mesh *mesh, const float *keys, size_t count, const texopt_model *model,
                                      const texopt_domain *dom, char *err, size_t err_len)
{
    weld_map map;
    uint32_t *first_of = malloc(sizeof(uint32_t) * (count > 0 ? count : 1));
    mesh->vertex_of_model_vertex = malloc(sizeof(uint32_t) * (count > 0 ? count : 1));
    if (!first_of || !mesh->vertex_of_model_vertex || weld_map_init(&map, count, keys, 5) != 0) {
        free(first_of);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to weld %zu vertices", count);
    }
    /* first_of[v] = local index of the first model vertex of UV vertex v */
    size_t nv = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t first = weld_map_find_or_insert(&map, (uint32_t)i);
        if (first == i) {
            first_of[nv] = (uint32_t)i;
            mesh->vertex_of_model_vertex[i] = (uint32_t)nv++;
        } else
            mesh->vertex_of_model_vertex[i] = mesh->vertex_of_model_vertex[first];
    }
    free(map.slot);
    mesh->model_vertex_count = count;
    mesh->vertex_count = nv;
    mesh->texel = malloc(sizeof(double) * 2 * (nv > 0 ? nv : 1));
    mesh->model_vertex = malloc(sizeof(uint32_t) * (nv > 0 ? nv : 1));
    if (!mesh->texel || !mesh->model_vertex) {
        free(first_of);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu UV vertices", nv);
    }
    /* local index -> model vertex index, walking the primitives in order */
    size_t local = 0, v = 0;
    for (int k = 0; k < dom->primitive_count && v < nv; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        size_t end = local + prim->vertex_count;
        while (v < nv && first_of[v] < end) {
            mesh->model_vertex[v] = (uint32_t)(prim->first_vertex + (first_of[v] - local));
            v++;
        }
        local = end;
    }
    for (size_t i = 0; i < nv; i++) {
        const float *key = keys + 5 * (size_t)first_of[i];
        mesh->texel[2 * i] = (double)mesh->width * (double)key[3];
        mesh->texel[2 * i + 1] = (double)mesh->height * (double)key[4];
    }
    free(first_of);
    return TEXOPT_OK;
}

/* Points: UV vertices with equal position. */
static texopt_status weld_points(texopt_mesh *mesh, const float *keys, char *err, size_t err_len)
{
    size_t nv = mesh->vertex_count;
    /* keys of UV vertices: the first model vertex's; gathered contiguously (stride 5) */
    float *vkeys = malloc(sizeof(float) * 3 * (nv > 0 ? nv : 1));
    uint32_t *first_vertex_of_point = malloc(sizeof(uint32_t) * (nv > 0 ? nv : 1));
    mesh->point_of = malloc(sizeof(uint32_t) * (nv > 0 ? nv : 1));
    weld_map map = {0};
    if (!vkeys || !first_vertex_of_point || !mesh->point_of || weld_map_init(&map, nv, NULL, 3) != 0) {
        free(vkeys);
        free(first_vertex_of_point);
        free(map.slot);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to weld %zu points", nv);
    }
    /* The local index of the first model vertex of each UV vertex: invert the weld. */
    for (size_t i = mesh->model_vertex_count; i-- > 0;) {
        uint32_t v = mesh->vertex_of_model_vertex[i];
        memcpy(vkeys + 3 * (size_t)v, keys + 5 * i, 3 * sizeof(float));
    }
    map.keys = vkeys;
    size_t np = 0;
    for (size_t v = 0; v < nv; v++) {
        uint32_t first = weld_map_find_or_insert(&map, (uint32_t)v);
        if (first == v) {
            first_vertex_of_point[np] = (uint32_t)v;
            mesh->point_of[v] = (uint32_t)np++;
        } else
            mesh->point_of[v] = mesh->point_of[first];
    }
    free(map.slot);
    mesh->point_count = np;
    mesh->position = malloc(sizeof(double) * 3 * (np > 0 ? np : 1));
    if (!mesh->position) {
        free(vkeys);
        free(first_vertex_of_point);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu points", np);
    }
    for (size_t p = 0; p < np; p++)
        for (int c = 0; c < 3; c++)
            mesh->position[3 * p + c] = (double)vkeys[3 * (size_t)first_vertex_of_point[p] + c];
    free(vkeys);
    free(first_vertex_of_point);
    return TEXOPT_OK;
}

static texopt_status collect_triangles(texopt_mesh *mesh, const texopt_model *model, const texopt_domain *dom,
                                       char *err, size_t err_len)
{
    size_t nt = 0;
    for (int k = 0; k < dom->primitive_count; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        if (prim->first_triangle > model->triangle_count ||
            prim->triangle_count > model->triangle_count - prim->first_triangle)
            return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                               "primitive %d: triangles [%zu, +%zu) past the model's %zu", dom->primitives[k],
                               prim->first_triangle, prim->triangle_count, model->triangle_count);
        nt += prim->triangle_count;
    }
    if (nt >= UINT32_MAX)
        return texopt_fail(err, err_len, TEXOPT_E_LIMIT, "domain has %zu triangles", nt);
    size_t alloc = nt > 0 ? nt : 1;
    mesh->triangle_count = nt;
    mesh->triangle = malloc(sizeof(uint32_t) * 3 * alloc);
    mesh->model_triangle = malloc(sizeof(uint32_t) * alloc);
    mesh->area_3d = malloc(sizeof(double) * alloc);
    mesh->area_texel = malloc(sizeof(double) * alloc);
    mesh->flags = calloc(alloc, 1);
    mesh->chart_of = malloc(sizeof(uint32_t) * alloc);
    if (!mesh->triangle || !mesh->model_triangle || !mesh->area_3d || !mesh->area_texel || !mesh->flags ||
        !mesh->chart_of)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu triangles", nt);
    size_t t = 0, local = 0;
    for (int k = 0; k < dom->primitive_count; k++) {
        const texopt_primitive *prim = &model->primitives[dom->primitives[k]];
        for (size_t i = 0; i < prim->triangle_count; i++, t++) {
            size_t mt = prim->first_triangle + i;
            mesh->model_triangle[t] = (uint32_t)mt;
            for (int c = 0; c < 3; c++) {
                uint32_t mv = model->triangles[3 * mt + (size_t)c];
                if (mv < prim->first_vertex || mv - prim->first_vertex >= prim->vertex_count)
                    return texopt_fail(err, err_len, TEXOPT_E_MALFORMED,
                                       "primitive %d: triangle %zu uses vertex %u outside the "
                                       "primitive's vertices [%zu, %zu)",
                                       dom->primitives[k], i, mv, prim->first_vertex,
                                       prim->first_vertex + prim->vertex_count);
                mesh->triangle[3 * t + (size_t)c] = mesh->vertex_of_model_vertex[local + (mv - prim->first_vertex)];
            }
        }
        local += prim->vertex_count;
    }
    return TEXOPT_OK;
}

static double squared(double x)
{
    return x * x;
}

static int is_degenerate(double doubled_area, double longest_edge_sq)
{
    return doubled_area <= DEGENERATE_RELATIVE * longest_edge_sq;
}

int texopt_texel_triangle_degenerate(const double *a, const double *b, const double *c)
{
    double signed2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    double m1 = squared(b[0] - a[0]) + squared(b[1] - a[1]);
    double m2 = squared(c[0] - a[0]) + squared(c[1] - a[1]);
    double m3 = squared(c[0] - b[0]) + squared(c[1] - b[1]);
    return is_degenerate(fabs(signed2), fmax(m1, fmax(m2, m3)));
}

double texopt_layout_area(const texopt_mesh *mesh, const double *texel, const double *paid)
{
    double area = 0;
    for (size_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t *v = mesh->triangle + 3 * t;
        const double *a = texel + 2 * v[0], *b = texel + 2 * v[1], *c = texel + 2 * v[2];
        if (texopt_texel_triangle_degenerate(a, b, c))
            continue;
        double full = 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        area += paid ? paid[t] * full : full;
    }
    return area;
}

int texopt_mesh_plane_edges(const texopt_mesh *mesh, size_t t, double P[2][2])
{
    const uint32_t *v = mesh->triangle + 3 * t;
    return texopt_plane_edges(texopt_mesh_vertex_point(mesh, v[0]), texopt_mesh_vertex_point(mesh, v[1]),
                              texopt_mesh_vertex_point(mesh, v[2]), P);
}

static void measure_triangle(texopt_mesh *mesh, size_t t)
{
    const uint32_t *v = mesh->triangle + 3 * t;
    const double *p0 = texopt_mesh_vertex_point(mesh, v[0]);
    const double *p1 = texopt_mesh_vertex_point(mesh, v[1]);
    const double *p2 = texopt_mesh_vertex_point(mesh, v[2]);
    double e1[3], e2[3], e3[3];
    for (int c = 0; c < 3; c++) {
        e1[c] = p1[c] - p0[c];
        e2[c] = p2[c] - p0[c];
        e3[c] = p2[c] - p1[c];
    }
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double doubled = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double l1 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double l2 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double l3 = e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2];
    mesh->area_3d[t] = 0.5 * doubled;
    uint8_t flags = 0;
    if (is_degenerate(doubled, fmax(l1, fmax(l2, l3))))
        flags |= TEXOPT_TRI_DEGENERATE_3D;

    const double *a = mesh->texel + 2 * (size_t)v[0];
    const double *b = mesh->texel + 2 * (size_t)v[1];
    const double *c = mesh->texel + 2 * (size_t)v[2];
    mesh->area_texel[t] = texopt_signed_area(a, b, c);
    if (texopt_texel_triangle_degenerate(a, b, c))
        flags |= TEXOPT_TRI_DEGENERATE_UV;

    double w = mesh->width + WRAP_TOLERANCE_TEXELS, h = mesh->height + WRAP_TOLERANCE_TEXELS;
    for (int k = 0; k < 3; k++) {
        const double *p = mesh->texel + 2 * (size_t)v[k];
        if (p[0] < -WRAP_TOLERANCE_TEXELS || p[0] > w || p[1] < -WRAP_TOLERANCE_TEXELS || p[1] > h)
            flags |= TEXOPT_TRI_WRAPPED;
    }
    mesh->flags[t] = flags;
}

/* Charts by union-find over the UV vertices of each triangle, numbered by first triangle;
 * then each chart's orientation. */
static texopt_status find_charts(texopt_mesh *mesh, char *err, size_t err_len)
{
    size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    uint32_t *parent = malloc(sizeof(uint32_t) * (nv > 0 ? nv : 1));
    uint32_t *chart_of_root = malloc(sizeof(uint32_t) * (nv > 0 ? nv : 1));
    if (!parent || !chart_of_root) {
        free(parent);
        free(chart_of_root);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for charts");
    }
    for (size_t v = 0; v < nv; v++) {
        parent[v] = (uint32_t)v;
        chart_of_root[v] = UINT32_MAX;
    }
    for (size_t t = 0; t < nt; t++) {
        uf_union(parent, mesh->triangle[3 * t], mesh->triangle[3 * t + 1]);
        uf_union(parent, mesh->triangle[3 * t], mesh->triangle[3 * t + 2]);
    }
    size_t charts = 0;
    for (size_t t = 0; t < nt; t++) {
        uint32_t root = uf_find(parent, mesh->triangle[3 * t]);
        if (chart_of_root[root] == UINT32_MAX)
            chart_of_root[root] = (uint32_t)charts++;
        mesh->chart_of[t] = chart_of_root[root];
    }
    free(parent);
    free(chart_of_root);
    mesh->chart_count = charts;
    mesh->chart_sign = malloc(charts > 0 ? charts : 1);
    double *balance = calloc(charts > 0 ? charts : 1, sizeof(double));
    if (!mesh->chart_sign || !balance) {
        free(balance);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu charts", charts);
    }
    /* positive minus negative area: its sign is the area-weighted majority */
    for (size_t t = 0; t < nt; t++)
        if (!(mesh->flags[t] & TEXOPT_TRI_DEGENERATE_UV))
            balance[mesh->chart_of[t]] += mesh->area_texel[t];
    for (size_t c = 0; c < charts; c++)
        mesh->chart_sign[c] = balance[c] < 0 ? -1 : 1;
    free(balance);
    return TEXOPT_OK;
}

/* Triangles around each point (CSR). A triangle with two corners on one point (3D
 * degenerate) is listed once for it. */
static texopt_status build_point_triangles(texopt_mesh *mesh, char *err, size_t err_len)
{
    size_t np = mesh->point_count, nt = mesh->triangle_count;
    mesh->point_triangle_start = calloc(np + 1, sizeof(uint32_t));
    mesh->point_triangle = malloc(sizeof(uint32_t) * (3 * nt > 0 ? 3 * nt : 1));
    uint32_t *fill = malloc(sizeof(uint32_t) * (np > 0 ? np : 1));
    if (!mesh->point_triangle_start || !mesh->point_triangle || !fill) {
        free(fill);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for one-rings");
    }
    for (size_t pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < nt; t++) {
            uint32_t p[3];
            for (int c = 0; c < 3; c++)
                p[c] = mesh->point_of[mesh->triangle[3 * t + (size_t)c]];
            for (int c = 0; c < 3; c++) {
                if ((c > 0 && p[c] == p[0]) || (c > 1 && p[c] == p[1]))
                    continue;
                if (pass == 0)
                    mesh->point_triangle_start[p[c] + 1]++;
                else
                    mesh->point_triangle[fill[p[c]]++] = (uint32_t)t;
            }
        }
        if (pass == 0) {
            for (size_t i = 0; i < np; i++)
                mesh->point_triangle_start[i + 1] += mesh->point_triangle_start[i];
            for (size_t i = 0; i < np; i++)
                fill[i] = mesh->point_triangle_start[i];
        }
    }
    free(fill);
    return TEXOPT_OK;
}

/* An edge (pair of UV vertices, smaller index in the high half) and one triangle using it. */
typedef struct tri_edge {
    uint64_t key;
    uint32_t triangle;
} tri_edge;

static int edge_before(const tri_edge *x, const tri_edge *y)
{
    return x->key < y->key || (x->key == y->key && x->triangle < y->triangle);
}

/* Every (edge, triangle) pair sorted by edge, then triangle, so the triangles of an edge are
 * adjacent. Counting sort on the smaller vertex, then insertion sort inside each vertex's
 * bucket (a few edges): linear time, where qsort took most of a million-triangle build. */
static tri_edge *sorted_edges(const texopt_mesh *mesh, size_t *count)
{
    size_t nt = mesh->triangle_count, nv = mesh->vertex_count, ne = 0;
    tri_edge *edges = malloc(sizeof(tri_edge) * (3 * nt > 0 ? 3 * nt : 1));
    size_t *start = calloc(nv + 1, sizeof(size_t));
    if (!edges || !start) {
        free(edges);
        free(start);
        return NULL;
    }
    for (int pass = 0; pass < 2; pass++) {
        for (size_t t = 0; t < nt; t++)
            for (int c = 0; c < 3; c++) {
                uint32_t a = mesh->triangle[3 * t + (size_t)c], b = mesh->triangle[3 * t + (size_t)(c + 1) % 3];
                if (a == b)
                    continue;
                uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
                if (pass == 0)
                    start[lo + 1]++;
                else
                    edges[start[lo]++] = (tri_edge){((uint64_t)lo << 32) | hi, (uint32_t)t};
            }
        if (pass == 0) {
            for (size_t v = 0; v < nv; v++)
                start[v + 1] += start[v];
            ne = start[nv]; /* start[v] now begins bucket v; pass 1 advances it */
        }
    }
    free(start);
    /* buckets are contiguous runs of equal lo: insertion sort finishes the order */
    for (size_t i = 1; i < ne; i++) {
        tri_edge e = edges[i];
        size_t j = i;
        while (j > 0 && (edges[j - 1].key >> 32) == (e.key >> 32) && edge_before(&e, &edges[j - 1])) {
            edges[j] = edges[j - 1];
            j--;
        }
        edges[j] = e;
    }
    *count = ne;
    return edges;
}

/* Vertices on an edge that only one triangle uses. */
static texopt_status find_boundary(texopt_mesh *mesh, const tri_edge *edges, size_t ne, char *err, size_t err_len)
{
    mesh->vertex_on_boundary = calloc(mesh->vertex_count > 0 ? mesh->vertex_count : 1, 1);
    if (!mesh->vertex_on_boundary)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for chart boundaries");
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && edges[j].key == edges[i].key)
            j++;
        if (j - i == 1) {
            mesh->vertex_on_boundary[edges[i].key >> 32] = 1;
            mesh->vertex_on_boundary[edges[i].key & 0xffffffffu] = 1;
        }
        i = j;
    }
    return TEXOPT_OK;
}

static int orientation(const texopt_mesh *mesh, uint32_t t)
{
    if (mesh->flags[t] & TEXOPT_TRI_DEGENERATE_UV)
        return 0;
    return mesh->area_texel[t] < 0 ? -1 : 1;
}

/* Flipped triangles: orientation patches are the triangles joined through shared UV edges
 * with equal orientation; a patch against its chart's orientation holding less than
 * FOLD_PATCH_FRACTION of the chart's area is a fold-over, and its triangles are FLIPPED. A
 * larger one is a deliberately mirrored part (halves welded at their mirror line). */
static texopt_status mark_flipped(texopt_mesh *mesh, const tri_edge *edges, size_t ne, char *err, size_t err_len)
{
    size_t nt = mesh->triangle_count, nc = mesh->chart_count;
    uint32_t *parent = malloc(sizeof(uint32_t) * (nt > 0 ? nt : 1));
    double *patch_area = calloc(nt > 0 ? nt : 1, sizeof(double));
    double *chart_area = calloc(nc > 0 ? nc : 1, sizeof(double));
    if (!parent || !patch_area || !chart_area) {
        free(parent);
        free(patch_area);
        free(chart_area);
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for orientation patches");
    }
    for (size_t t = 0; t < nt; t++)
        parent[t] = (uint32_t)t;
    for (size_t i = 0; i + 1 < ne; i++)
        if (edges[i].key == edges[i + 1].key) {
            uint32_t a = edges[i].triangle, b = edges[i + 1].triangle;
            int oa = orientation(mesh, a);
            if (oa != 0 && oa == orientation(mesh, b))
                uf_union(parent, a, b);
        }
    for (size_t t = 0; t < nt; t++) {
        if (orientation(mesh, (uint32_t)t) == 0)
            continue;
        double a = fabs(mesh->area_texel[t]);
        patch_area[uf_find(parent, (uint32_t)t)] += a;
        chart_area[mesh->chart_of[t]] += a;
    }
    for (size_t t = 0; t < nt; t++) {
        int o = orientation(mesh, (uint32_t)t);
        uint32_t c = mesh->chart_of[t];
        if (o != 0 && o != mesh->chart_sign[c] &&
            patch_area[uf_find(parent, (uint32_t)t)] < FOLD_PATCH_FRACTION * chart_area[c])
            mesh->flags[t] |= TEXOPT_TRI_FLIPPED;
    }
    free(parent);
    free(patch_area);
    free(chart_area);
    return TEXOPT_OK;
}

/* Boundary vertices and flipped triangles, which both need the triangles of each edge. */
static texopt_status analyse_edges(texopt_mesh *mesh, char *err, size_t err_len)
{
    size_t ne = 0;
    tri_edge *edges = sorted_edges(mesh, &ne);
    if (!edges)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu edges", 3 * mesh->triangle_count);
    texopt_status st = find_boundary(mesh, edges, ne, err, err_len);
    if (st == TEXOPT_OK)
        st = mark_flipped(mesh, edges, ne, err, err_len);
    free(edges);
    return st;
}

texopt_status texopt_mesh_create(texopt_mesh **out, const texopt_model *model, int domain, char *err, size_t err_len)
{
    if (!out)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "mesh: no output pointer");
    *out = NULL;
    if (!model || domain < 0 || domain >= model->domain_count)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT,
                           "mesh: texture domain %d does not exist (model has %d)", domain,
                           model ? model->domain_count : 0);
    if (!model->uvs || !model->positions || !model->triangles)
        return texopt_fail(err, err_len, TEXOPT_E_UNSUPPORTED, "mesh: the model has no %s",
                           !model->uvs ? "TEXCOORD_0" : "geometry");
    const texopt_domain *dom = &model->domains[domain];
    if (dom->width <= 0 || dom->height <= 0)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "mesh: domain %d has texel frame %dx%d", domain,
                           dom->width, dom->height);
    for (int k = 0; k < dom->primitive_count; k++)
        if (dom->primitives[k] < 0 || dom->primitives[k] >= model->primitive_count)
            return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "mesh: domain %d lists primitive %d of %d",
                               domain, dom->primitives[k], model->primitive_count);
    texopt_mesh *mesh = calloc(1, sizeof *mesh);
    if (!mesh)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for a mesh");
    mesh->domain = domain;
    mesh->width = dom->width;
    mesh->height = dom->height;
    mesh->wrap_s = dom->wrap_s;
    mesh->wrap_t = dom->wrap_t;
    float *keys = NULL;
    size_t count = 0;
    texopt_status st = gather_vertices(model, dom, &keys, &count, err, err_len);
    if (st == TEXOPT_OK)
        st = weld_uv_vertices(mesh, keys, count, model, dom, err, err_len);
    if (st == TEXOPT_OK)
        st = weld_points(mesh, keys, err, err_len);
    free(keys);
    if (st == TEXOPT_OK)
        st = collect_triangles(mesh, model, dom, err, err_len);
    if (st == TEXOPT_OK)
        for (size_t t = 0; t < mesh->triangle_count; t++)
            measure_triangle(mesh, t);
    if (st == TEXOPT_OK)
        st = find_charts(mesh, err, err_len);
    if (st == TEXOPT_OK)
        st = build_point_triangles(mesh, err, err_len);
    if (st == TEXOPT_OK)
        st = analyse_edges(mesh, err, err_len);
    if (st != TEXOPT_OK) {
        texopt_mesh_destroy(mesh);
        return st;
    }
    *out = mesh;
    return TEXOPT_OK;
}

void texopt_mesh_destroy(texopt_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->texel);
    free(mesh->point_of);
    free(mesh->model_vertex);
    free(mesh->vertex_of_model_vertex);
    free(mesh->position);
    free(mesh->triangle);
    free(mesh->model_triangle);
    free(mesh->area_3d);
    free(mesh->area_texel);
    free(mesh->flags);
    free(mesh->chart_of);
    free(mesh->chart_sign);
    free(mesh->vertex_on_boundary);
    free(mesh->point_triangle_start);
    free(mesh->point_triangle);
    free(mesh);
}

/* Whether triangle t has a corner on point p. */
static int touches_point(const texopt_mesh *mesh, uint32_t t, uint32_t p)
{
    for (int c = 0; c < 3; c++)
        if (mesh->point_of[mesh->triangle[3 * (size_t)t + (size_t)c]] == p)
            return 1;
    return 0;
}

size_t texopt_mesh_one_ring(const texopt_mesh *mesh, uint32_t triangle, uint32_t *out, size_t cap)
{
    if (!mesh || triangle >= mesh->triangle_count)
        return 0;
    size_t n = 0;
    if (cap > 0)
        out[0] = triangle;
    n = 1;
    uint32_t p[3];
    for (int c = 0; c < 3; c++)
        p[c] = mesh->point_of[mesh->triangle[3 * (size_t)triangle + (size_t)c]];
    for (int c = 0; c < 3; c++) {
        if ((c > 0 && p[c] == p[0]) || (c > 1 && p[c] == p[1]))
            continue;
        /* A triangle around an earlier corner point was listed already. */
        for (uint32_t i = mesh->point_triangle_start[p[c]]; i < mesh->point_triangle_start[p[c] + 1]; i++) {
            uint32_t t = mesh->point_triangle[i];
            if (t == triangle || (c > 0 && touches_point(mesh, t, p[0])) || (c > 1 && touches_point(mesh, t, p[1])))
                continue;
            if (n < cap)
                out[n] = t;
            n++;
        }
    }
    return n;
}
