/* map_check.c - q of every map, and the per-map resize rule (map_check.h). */
#include "map_check.h"

#include <math.h>
#include <string.h>

#include "lit_shade.h"
#include "meshrender.h"

const char *texopt_map_measure_name(int m)
{
    return m == TEXOPT_MAP_LIT ? "lit" : texopt_texture_key_name(m);
}

/* Whether a primitive of `domain` (< 0: any) binds texture key `key`. */
static int domain_binds(const texopt_model *model, int domain, int key)
{
    for (int p = 0; p < model->primitive_count; p++)
        if ((domain < 0 || model->primitives[p].domain == domain) && texopt_meshrender_binding(model, p, key))
            return 1;
    return 0;
}

void texopt_map_measures(const texopt_model *model, int domain, int *measured)
{
    static const int lit_slots[] = {TEXOPT_SLOT_BASE_COLOR, TEXOPT_SLOT_METALLIC_ROUGHNESS, TEXOPT_SLOT_NORMAL,
                                    TEXOPT_SLOT_OCCLUSION, TEXOPT_SLOT_EMISSIVE};
    int lit = 0;
    for (int m = 0; m < TEXOPT_TEXTURE_KEY_COUNT; m++)
        measured[m] = m == TEXOPT_SLOT_BASE_COLOR || domain_binds(model, domain, m);
    for (size_t i = 0; i < sizeof lit_slots / sizeof *lit_slots; i++)
        lit |= domain_binds(model, domain, lit_slots[i]);
    measured[TEXOPT_MAP_LIT] = lit && texopt_lit_has_maps(model);
}

texopt_status texopt_map_evaluate(const texopt_model *reference, const texopt_model *const *candidates, int n,
                                  const texopt_evaluate_options *base, const int *measured, texopt_map_q *out,
                                  char *err, size_t err_len)
{
    if (n < 1 || n > TEXOPT_MAP_MAX_CANDIDATES)
        return texopt_fail(err, err_len, TEXOPT_E_INVALID_ARGUMENT, "map check: %d candidates", n);
    texopt_evaluation ev[TEXOPT_MAP_MAX_CANDIDATES];
    for (int c = 0; c < n; c++) {
        memset(&out[c], 0, sizeof out[c]);
        memcpy(out[c].measured, measured, sizeof out[c].measured);
    }
    texopt_status st = TEXOPT_OK;
    for (int m = 0; m < TEXOPT_MAP_MEASURES && st == TEXOPT_OK; m++) {
        if (!measured[m])
            continue;
        texopt_evaluate_options opt = *base;
        opt.triangle_error = NULL;
        opt.triangle_error_edges = 0;
        opt.reference_views = NULL;
        opt.lit = m == TEXOPT_MAP_LIT;
        opt.texture = opt.lit ? TEXOPT_SLOT_BASE_COLOR : m;
        st = texopt_evaluate_many(reference, candidates, n, &opt, ev, err, err_len);
        for (int c = 0; c < n && st == TEXOPT_OK; c++)
            out[c].q[m] = ev[c].q;
    }
    return st;
}

/* q layout / q resize, with the conventions of texopt_map_layout_wins. */
static double loss_ratio(double layout, double resize)
{
    if (resize > 0)
        return layout / resize;
    return layout > 0 ? INFINITY : 1.0;
}

/* Over measures [from, to) measured by both and differing: whether the layout is above the
 * resize on one, below on one, and the one with the largest ratio (-1 when none differ). */
static int worst_measure(const texopt_map_q *layout, const texopt_map_q *resize, int from, int to, int *worse,
                         int *better)
{
    int decider = -1;
    double worst = -1;
    for (int m = from; m < to; m++) {
        if (!layout->measured[m] || !resize->measured[m] || layout->q[m] == resize->q[m])
            continue;
        double r = loss_ratio(layout->q[m], resize->q[m]);
        *worse |= layout->q[m] > resize->q[m];
        *better |= layout->q[m] < resize->q[m];
        if (r > worst) {
            worst = r;
            decider = m;
        }
    }
    return decider;
}

int texopt_map_layout_wins(const texopt_map_q *layout, const texopt_map_q *resize, int *decided_by)
{
    int worse_map = 0, better = 0, worse_lit = 0;
    int map = worst_measure(layout, resize, 0, TEXOPT_MAP_LIT, &worse_map, &better);
    int lit = worst_measure(layout, resize, TEXOPT_MAP_LIT, TEXOPT_MAP_MEASURES, &worse_lit, &better);
    int decider = map >= 0 && (worse_map || !worse_lit) ? map : lit >= 0 ? lit : TEXOPT_SLOT_BASE_COLOR;
    if (decided_by)
        *decided_by = decider;
    return better && !worse_map && !worse_lit;
}
