/* input_method.h - method "input": a domain's input layout kept, its images resized.
 *
 * Does: keep the input layout as it is (UVs untouched, seams, overlaps and wrapping
 * included) and resize each image of the domain with Lanczos-3 (lanczos.h, Pillow's rules)
 * to the budget: a relative cost c_r scales both sides by sqrt(c_r) (rounded to whole
 * texels), a texture size is taken as given. Besides method "input" it is what every layout
 * method falls back to for a domain it keeps in its input layout (domain_keep.h). Does not:
 * decide when a domain falls back. */
#ifndef TEXOPT_INPUT_METHOD_H
#define TEXOPT_INPUT_METHOD_H

#include "job_state.h"

/* The domain frame's size under method "input" at the budget of params. */
void job_input_frame(const texopt_domain *dom, const texopt_params *params, int *ow, int *oh);

/* Domain d's images resized to the budget of run->p into run->out, its statistics in
 * run->domains[d]; progress over [from, to] of the job. */
texopt_status job_run_input_method(texopt_job *job, const layout_run *run, int d, double from, double to, char *err,
                                   size_t err_len);

#endif
