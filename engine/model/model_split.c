/* model_split.c - one model vertex per (vertex, group) pair (model_split.h). */
#include "model_split.h"

#include <stdlib.h>
#include <string.h>

typedef struct corner_key {
    uint32_t vertex, group, corner; /* vertex local to its primitive; corner in the primitive */
} corner_key;

static int compare_keys(const void *a, const void *b)
{
    const corner_key *x = a, *y = b;
    if (x->vertex != y->vertex)
        return x->vertex < y->vertex ? -1 : 1;
    if (x->group != y->group)
        return x->group < y->group ? -1 : 1;
    return (x->corner > y->corner) - (x->corner < y->corner);
}

/* The primitive's corners renumbered (local indices into local[]): a vertex's first group
 * keeps its index, each further group a copy numbered from the primitive's vertex count;
 * source[] receives, per copy, the local vertex it repeats. Returns the copies made. */
static size_t split_primitive(const texopt_model *model, const texopt_primitive *tp, const uint32_t *corner_group,
                              corner_key *keys, uint32_t *local, uint32_t *source)
{
    size_t n = 3 * tp->triangle_count, copies = 0;
    for (size_t c = 0; c < n; c++) {
        size_t corner = 3 * tp->first_triangle + c;
        keys[c] =
            (corner_key){model->triangles[corner] - (uint32_t)tp->first_vertex, corner_group[corner], (uint32_t)c};
    }
    qsort(keys, n, sizeof *keys, compare_keys);
    uint32_t index = 0;
    for (size_t i = 0; i < n; i++) {
        int new_vertex = i == 0 || keys[i].vertex != keys[i - 1].vertex;
        int new_group = !new_vertex && keys[i].group != keys[i - 1].group;
        if (new_vertex)
            index = keys[i].vertex;
        else if (new_group) {
            index = (uint32_t)(tp->vertex_count + copies);
            source[copies++] = keys[i].vertex;
        }
        local[keys[i].corner] = index;
    }
    return copies;
}

typedef struct split_arrays {
    float *positions, *uvs, *normals;
    uint32_t *triangles, *file_vertex;
} split_arrays;

/* Copies primitive p's vertices (its own, then its copies) into the new arrays from `at`. */
static void copy_primitive(const texopt_model *model, const texopt_primitive *tp, const uint32_t *local,
                           const uint32_t *source, size_t copies, size_t at, split_arrays *a)
{
    for (size_t v = 0; v < tp->vertex_count + copies; v++) {
        uint32_t from_local = v < tp->vertex_count ? (uint32_t)v : source[v - tp->vertex_count];
        size_t from = tp->first_vertex + from_local;
        memcpy(a->positions + 3 * (at + v), model->positions + 3 * from, 3 * sizeof(float));
        if (model->uvs)
            memcpy(a->uvs + 2 * (at + v), model->uvs + 2 * from, 2 * sizeof(float));
        if (model->normals)
            memcpy(a->normals + 3 * (at + v), model->normals + 3 * from, 3 * sizeof(float));
        a->file_vertex[at + v] = model->file_vertex ? model->file_vertex[from] : from_local;
    }
    for (size_t c = 0; c < 3 * tp->triangle_count; c++)
        a->triangles[3 * tp->first_triangle + c] = (uint32_t)at + local[c];
}

texopt_status texopt_model_split_vertices(texopt_model *model, const uint32_t *corner_group, size_t *added, char *err,
                                          size_t err_len)
{
    if (added)
        *added = 0;
    size_t most = 0, total = 0;
    for (int p = 0; p < model->primitive_count; p++)
        most = 3 * model->primitives[p].triangle_count > most ? 3 * model->primitives[p].triangle_count : most;
    corner_key *keys = malloc((most ? most : 1) * sizeof *keys);
    uint32_t *local = malloc((3 * model->triangle_count + 1) * sizeof *local);
    uint32_t *source = malloc((3 * model->triangle_count + 1) * sizeof *source);
    size_t *copies = calloc((size_t)model->primitive_count + 1, sizeof *copies);
    split_arrays a = {0};
    texopt_status st = TEXOPT_OK;
    if (!keys || !local || !source || !copies)
        st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to split %zu vertices", model->vertex_count);
    /* First pass: how many copies each primitive needs (the renumbering is redone below). */
    for (int p = 0; st == TEXOPT_OK && p < model->primitive_count; p++) {
        const texopt_primitive *tp = &model->primitives[p];
        copies[p] = split_primitive(model, tp, corner_group, keys, local, source);
        total += copies[p];
    }
    size_t count = model->vertex_count + total;
    if (st == TEXOPT_OK && count > UINT32_MAX)
        st = texopt_fail(err, err_len, TEXOPT_E_LIMIT, "splitting gives more than 2^32 vertices");
    if (st == TEXOPT_OK) {
        a.positions = malloc(3 * (count + 1) * sizeof(float));
        a.uvs = model->uvs ? malloc(2 * (count + 1) * sizeof(float)) : NULL;
        a.normals = model->normals ? malloc(3 * (count + 1) * sizeof(float)) : NULL;
        a.triangles = malloc((3 * model->triangle_count + 1) * sizeof(uint32_t));
        a.file_vertex = malloc((count + 1) * sizeof(uint32_t));
        if (!a.positions || (model->uvs && !a.uvs) || (model->normals && !a.normals) || !a.triangles || !a.file_vertex)
            st = texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for %zu split vertices", count);
    }
    size_t at = 0;
    for (int p = 0; st == TEXOPT_OK && p < model->primitive_count; p++) {
        const texopt_primitive *tp = &model->primitives[p];
        split_primitive(model, tp, corner_group, keys, local, source);
        copy_primitive(model, tp, local, source, copies[p], at, &a);
        at += tp->vertex_count + copies[p];
    }
    if (st == TEXOPT_OK) {
        at = 0;
        for (int p = 0; p < model->primitive_count; p++) {
            model->primitives[p].first_vertex = at;
            model->primitives[p].vertex_count += copies[p];
            at += model->primitives[p].vertex_count;
        }
        free(model->positions);
        free(model->uvs);
        free(model->normals);
        free(model->triangles);
        free(model->file_vertex);
        model->positions = a.positions;
        model->uvs = a.uvs;
        model->normals = a.normals;
        model->triangles = a.triangles;
        model->file_vertex = a.file_vertex;
        model->vertex_count = count;
        a = (split_arrays){0};
        if (added)
            *added = total;
    }
    free(a.positions);
    free(a.uvs);
    free(a.normals);
    free(a.triangles);
    free(a.file_vertex);
    free(keys);
    free(local);
    free(source);
    free(copies);
    return st;
}
