/* input_method.h - method "input": a domain's input layout kept, its images resized.
 *
 * Does: keep the input layout as it is (UVs untouched, seams, overlaps and wrapping
 * included) and resize each image of the domain with Lanczos-3 (lanczos.h, Pillow's rules)
 * to the budget: a relative cost c_r scales both sides by sqrt(c_r) (rounded to whole
 * texels), a texture size is taken as given. Besides method "input" it is what every layout
 * method falls back to for a domain it keeps in its input layout (domain_keep.h). Does not:
 * decide when a domain falls back.
 *
 * Also here: the same layout with its images re-baked by the engine's fit instead of
 * resized, what the resize check (resize_check.h) offers beside the resize. */
#ifndef TEXOPT_INPUT_METHOD_H
#define TEXOPT_INPUT_METHOD_H

#include "job_state.h"

/* The domain frame's size under method "input" at the budget of params. */
void job_input_frame(const texopt_domain *dom, const texopt_params *params, int *ow, int *oh);

/* Domain d's images resized to the budget of run->p into run->out, its statistics in
 * run->domains[d]; progress over [from, to] of the job. */
texopt_status job_run_input_method(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                   size_t err_len);

/* Domain d's input layout kept and its images re-baked into it at the budget of run->p by
 * the engine's fit (bake_pool.h, rebake.h: the texels whose bilinear lookup matches the input
 * best) instead of resized, at the same file pixels as job_run_input_method; the layout
 * moved by whole tiles into the frame when it lies in another (REPEAT). The UVs the file
 * keeps are the input's. TEXOPT_E_UNSUPPORTED when the layout does not lie in one tile (a
 * texture tiled over the surface). */
texopt_status job_refit_input_layout(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                     size_t err_len);

#endif
