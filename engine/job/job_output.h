/* job_output.h - what one layout of the budget produces for the save step.
 *
 * Does: hold the new UVs, the re-baked images and, per domain, the solved and packed layouts
 * of a run (job_state.h layout_run); allocate, free and edit them. Does not: lay out or bake
 * (budget_layout.h, bake_pool.h). */
#ifndef TEXOPT_JOB_OUTPUT_H
#define TEXOPT_JOB_OUTPUT_H

#include <stddef.h>
#include <stdint.h>

#include "image.h"
#include "mesh.h"
#include "model.h"
#include "status.h"

typedef struct job_output {
    texopt_image *images; /* per model image; empty when kept */
    const texopt_image **edit_images;
    float *uvs; /* new TEXCOORD_0 of every model vertex, NULL when unchanged */
    int domain_count;
    double **solved;        /* per domain: stage 2's layout in input texels (kept for
                                    the loss share of a chosen candidate), NULL when none */
    double **packed;        /* per domain: the packed layout in output texels (kept to
                                    bake a chosen candidate's remaining images), NULL when none */
    int *packed_size;       /* per domain: its output width and height */
    texopt_mesh **cut;      /* per domain: the layout mesh cut into pieces (chart_cut.h) that
                          solved and packed are laid out on, NULL when not cut */
    uint32_t *corner_group; /* per model triangle corner: 1 + its piece where its domain
                               was cut, 0 elsewhere; NULL when no domain was cut */
    float *corner_uvs;      /* 2 per model corner: the new TEXCOORD_0 of cut corners */
} job_output;

/* Room for the images of the model and, when lays_out, the new UVs (a copy of the model's
 * TEXCOORD_0, zeros where it has none, that domains overwrite) and per-domain layouts. */
texopt_status job_output_alloc(const texopt_model *model, int lays_out, job_output *out, char *err, size_t err_len);

void job_output_destroy(job_output *o, int image_count);

/* Writes the new UVs of the domain's model vertices (output texels / output size). */
void job_output_write_uvs(const texopt_model *model, const texopt_mesh *mesh, const double *texel, int width,
                          int height, float *uvs);

/* A copy of the model's UVs (zeros where it has none) with room for one more pair, for a
 * domain to overwrite before job_output_mesh_with_uvs; NULL on no memory. */
float *job_output_uvs_copy(const texopt_model *model);

/* Domain d's mesh built from the model as if it held uvs (welded anew from them). */
texopt_status job_output_mesh_with_uvs(const texopt_model *model, int d, const float *uvs, texopt_mesh **mesh,
                                       char *err, size_t err_len);

/* As job_output_write_uvs for a layout on `cut` (texopt_mesh_cut_create of the domain's
 * layout mesh): the model vertices get their first piece's UV, and every corner of the
 * domain its own piece and UV in out's corner arrays (allocated here). */
texopt_status job_output_write_cut_uvs(const texopt_model *model, const texopt_mesh *cut, const double *texel,
                                       int width, int height, job_output *out, char *err, size_t err_len);

/* Domain d's corners back to uncut (its cut mesh freed), as when its input layout is
 * restored. */
void job_output_uncut_domain(const texopt_model *model, int d, job_output *out);

/* A copy of src's corner arrays into dst (none when src has none). */
texopt_status job_output_copy_corners(const texopt_model *model, const job_output *src, job_output *dst, char *err,
                                      size_t err_len);

/* The model as out writes it, into *view: model's with out's UVs, and, where a domain was
 * cut, its vertices split where pieces meet (model_split.h) with each corner's UV. The
 * view shares model's images, materials and document; free it with job_output_view_free.
 * What the evaluation renders and the save writes. */
texopt_status job_output_view(const texopt_model *model, const job_output *out, texopt_model *view, char *err,
                              size_t err_len);

void job_output_view_free(const texopt_model *model, texopt_model *view);

/* The side of an image scaled by factor, in [1, 16384]. */
int job_scaled_side(int side, double factor);

/* Output size of one image of the domain: proportional to the domain frame's new size. */
void job_image_output_size(const texopt_image *img, const texopt_domain *dom, int out_w, int out_h, int *w, int *h);

/* Domain d's vertices in uvs back to the model's TEXCOORD_0 (as job_output_alloc copied them). */
void job_output_restore_uvs(const texopt_model *model, int d, float *uvs);

#endif
