/* map_check.h - q of every map a viewer draws, and the per-map rule "never worse than a resize".
 *
 * A material binds several textures (base colour, metallic-roughness, normal, occlusion,
 * emissive, extension textures); a viewer draws all of them, lit. A layout that wins on base
 * colour can lose on another map (issue 45: an emissive map at 1.77x a resize's loss), so a
 * layout is judged on each: the whole-mesh loss q (evaluate.h) of each texture bound, in the
 * channels its binding reads, normal maps in the reference's tangent frame, and the lit luma
 * of them all (evaluate.h `lit`) when the model has a map a light reads besides base colour.
 *
 * Measures are indexed as compare.h's q_by_texture: the texture keys (texture_keys.h), then
 * lit at TEXOPT_MAP_LIT.
 *
 * Does not: lay out, bake or choose a layout itself (pipeline.c keep_resize_if_better reads
 * texopt_map_layout_wins). */
#ifndef TEXOPT_MAP_CHECK_H
#define TEXOPT_MAP_CHECK_H

#include <stddef.h>

#include "evaluate.h"
#include "model.h"
#include "status.h"
#include "texture_keys.h"

#define TEXOPT_MAP_LIT TEXOPT_TEXTURE_KEY_COUNT
#define TEXOPT_MAP_MEASURES (TEXOPT_TEXTURE_KEY_COUNT + 1)
#define TEXOPT_MAP_MAX_CANDIDATES 8 /* texopt_map_evaluate's n */

/* q of one candidate per measure; q[m] is meaningful where measured[m] is nonzero. */
typedef struct texopt_map_q {
    int measured[TEXOPT_MAP_MEASURES];
    double q[TEXOPT_MAP_MEASURES];
} texopt_map_q;

/* The name of measure m: the texture key's (texopt_texture_key_name), or "lit". */
const char *texopt_map_measure_name(int m);

/* Which measures show domain `domain` (< 0: the whole model) into measured[0..
 * TEXOPT_MAP_MEASURES): each texture a primitive of it binds through its material, and lit
 * when the model has a map a light reads besides base colour (lit_shade.h
 * texopt_lit_has_maps) and the domain binds one of the lit textures. Base colour is always
 * measured (the paper's q, defined for any model). */
void texopt_map_measures(const texopt_model *model, int domain, int *measured);

/* q of each measure in `measured` for candidates[0..n), n <= TEXOPT_MAP_MAX_CANDIDATES,
 * against reference, into out[0..n):
 * one texopt_evaluate_many pass per measure, with base's resolution, cameras, lookups,
 * threads and monitor (its texture, lit, triangle_error and reference_views are not read). */
texopt_status texopt_map_evaluate(const texopt_model *reference, const texopt_model *const *candidates, int n,
                                  const texopt_evaluate_options *base, const int *measured, texopt_map_q *out,
                                  char *err, size_t err_len);

/* The per-map rule: the layout wins when no measure of it is above the resize's and one is
 * below (all equal, as at the input's own pixels, keeps the resize: it changes nothing).
 * *decided_by becomes the texture, among those where the two differ, with the largest ratio
 * q layout / q resize (a loss over a resize at 0 counts as infinite): the map that lost when
 * the resize is kept, the closest call when the layout is; lit when only lit lost or only lit
 * differs; base colour when nothing differs. Both must measure the same measures. */
int texopt_map_layout_wins(const texopt_map_q *layout, const texopt_map_q *resize, int *decided_by);

#endif
