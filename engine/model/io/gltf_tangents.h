/* gltf_tangents.h - whether a primitive of a loaded model carries its own TANGENT attribute.
 *
 * The re-bake (rebake.h) must know it: a renderer uses stored tangents as they are, so a
 * normal map re-baked into a rotated layout keeps its XY; without stored tangents the
 * renderer derives them from the new UVs (MikkTSpace) and the XY must turn with the layout.
 * Reads the document io/gltf_io.h keeps in model->document; changes nothing. Supports the
 * re-bake that follows Sun et al. 2022, "Efficient Texture Parameterization Driven by
 * Perceptual-Loss-on-Screen"; implements no part of the method. */
#ifndef TEXOPT_GLTF_TANGENTS_H
#define TEXOPT_GLTF_TANGENTS_H

#ifdef __cplusplus
extern "C" {
#endif

#include "model.h"

/* 1 when model primitive `primitive` has a TANGENT attribute in its file, 0 when it has
 * none, when the model has no document (built in memory) or the index is out of range. */
int texopt_primitive_has_tangents(const texopt_model *model, int primitive);

#ifdef __cplusplus
}
#endif

#endif
