/* model_split.h - duplicating model vertices so that each belongs to one group of triangles.
 *
 * New charts (param/rechart.h) may cut the surface where the input's vertices are shared:
 * a vertex then needs one UV per chart. Splitting gives every (vertex, group) pair its own
 * model vertex: the first group of a vertex (the smallest value) keeps it, each further one
 * gets a copy appended to the vertex's primitive, with the same position, UV and normal. The model
 * draws exactly as before (same positions, same UVs); model->file_vertex records which file
 * vertex each copy repeats, so saving (io/gltf_io.h) writes the copies' other attributes
 * and new indices. Does not: weld, reorder triangles, or touch images and domains. */
#ifndef TEXOPT_MODEL_SPLIT_H
#define TEXOPT_MODEL_SPLIT_H

#include <stddef.h>
#include <stdint.h>

#include "model.h"
#include "status.h"

/* corner_group: 3 per model triangle, the group of each corner (any value; corners of one
 * vertex with equal values share it). *added (may be NULL) receives the vertices copied.
 * On failure the model is unchanged. */
texopt_status texopt_model_split_vertices(texopt_model *model, const uint32_t *corner_group, size_t *added, char *err,
                                          size_t err_len);

#endif
