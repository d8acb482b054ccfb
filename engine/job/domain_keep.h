/* domain_keep.h - when a layout method keeps a domain's input layout, and why.
 *
 * Does: the rules, each with its reason in the statistics (input_layout_kept). At job
 * creation: a domain of which nothing can be seen (every triangle without area in 3D), whose
 * layout covers no texel centre (UVs picking a colour from a palette) or one of whose
 * textures is magnified NEAREST (pixel art, whose texel blocks no new layout keeps on their
 * grid) is kept as it is (DOMAIN_KEPT_AS_IS); a model with no other domain is refused. A
 * domain whose UVs repeat its texture (a tiling texture) keeps its input layout resized as by
 * method "input" (DOMAIN_INPUT_RESIZED): an atlas would need the repeats' texels. Per budget:
 * a domain whose new layout would pack into over twice the pixels of its input layout resized
 * to the budget, or fit a texture size at no scale (charts of a texel or less, mostly
 * gutter), keeps its input layout resized; so does one whose new layout fails the layout
 * check (layout_check.h: overlap, fold-over or a triangle far above its target). Does not:
 * resize (input_method.h) or judge layouts by their look (resize_check.h). */
#ifndef TEXOPT_DOMAIN_KEEP_H
#define TEXOPT_DOMAIN_KEEP_H

#include "budget.h"
#include "job_state.h"

/* Each of these returns 1 and marks jd->kept, with the reason in ds, when its rule keeps the
 * domain. Every triangle without area in 3D: */
int job_keep_if_flat(job_domain *jd, texopt_domain_stats *ds);
/* No texel centre covered (jd->input_coverage measured): */
int job_keep_if_no_texels(const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds);
/* A texture magnified NEAREST: */
int job_keep_if_nearest(const texopt_model *model, const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds);
/* A tiling texture (jd->share and jd->paid found): */
int job_keep_if_tiling(const texopt_domain *dom, job_domain *jd, texopt_domain_stats *ds);

/* A layout method with no domain to lay out has nothing to do: refused with the first
 * domain's reason rather than writing the input again. */
texopt_status job_check_something_laid_out(const texopt_job *job, char *err, size_t err_len);

/* A domain kept as it is keeps its UVs (job_output_alloc copied them) and its images' bytes,
 * whatever the budget: its statistics say so. */
void job_keep_domain(const texopt_model *model, int d, texopt_domain_stats *ds);

/* Whether the domain keeps its input layout rather than the layout of *br (st: the budget's
 * status), with the reason in ds. */
int job_input_layout_packs_better(const texopt_model *model, const texopt_mesh *mesh, const texopt_params *p,
                                  const texopt_budget_result *br, texopt_status st, texopt_domain_stats *ds);

/* Whether domain d's packed layout (on `laid`: its layout mesh, or that mesh cut into
 * pieces) fails the layout check (against the targets it was solved from), recorded in
 * run->domains[d] with the reason in its input_layout_kept; *st: the check's status. */
int job_layout_fails_check(const texopt_job *job, const layout_run *run, int d, const texopt_mesh *laid,
                           const double *packed, const texopt_budget_result *br, texopt_status *st, char *err,
                           size_t err_len);

#endif
