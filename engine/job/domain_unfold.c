/* domain_unfold.c - overlapping input charts laid out anew under --bijective (domain_unfold.h). */
#include "domain_unfold.h"

#include <stdlib.h>
#include <string.h>

#include "chart_unfold.h"

/* Whether layout has mesh's vertices, triangles and charts (the welding of its UVs found the
 * same ones). */
static int same_structure(const texopt_mesh *mesh, const texopt_mesh *layout)
{
    return layout->vertex_count == mesh->vertex_count && layout->triangle_count == mesh->triangle_count &&
           layout->chart_count == mesh->chart_count &&
           !memcmp(layout->triangle, mesh->triangle, 3 * mesh->triangle_count * sizeof *mesh->triangle) &&
           !memcmp(layout->chart_of, mesh->chart_of, mesh->triangle_count * sizeof *mesh->chart_of);
}

/* jd->layout: the domain's mesh built from the model with texel's UVs; left NULL when its
 * welding differs from the input's. */
static texopt_status layout_mesh(texopt_job *job, int d, const double *texel, char *err, size_t err_len)
{
    job_domain *jd = &job->domains[d];
    float *uvs = job_output_uvs_copy(job->model);
    if (!uvs)
        return texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory for the unfolded charts' UVs");
    job_output_write_uvs(job->model, jd->mesh, texel, jd->mesh->width, jd->mesh->height, uvs);
    texopt_mesh *layout = NULL;
    texopt_status st = job_output_mesh_with_uvs(job->model, d, uvs, &layout, err, err_len);
    free(uvs);
    if (st == TEXOPT_OK && !same_structure(jd->mesh, layout)) {
        texopt_mesh_destroy(layout);
        layout = NULL;
    }
    jd->layout = layout;
    return st;
}

texopt_status job_unfold_domain(texopt_job *job, int d, char *err, size_t err_len)
{
    job_domain *jd = &job->domains[d];
    texopt_unfold_report *rep = &job->stats.domains[d].unfold;
    double *texel = malloc(2 * (jd->mesh->vertex_count ? jd->mesh->vertex_count : 1) * sizeof *texel);
    texopt_status st =
        texel ? TEXOPT_OK : texopt_fail(err, err_len, TEXOPT_E_NOMEM, "no memory to unfold domain %d", d);
    if (st == TEXOPT_OK)
        st = texopt_unfold_groups(jd->mesh, jd->share, texel, rep, err, err_len);
    int moved = rep->unfolded > 0 || rep->followed > 0;
    if (st == TEXOPT_OK && moved)
        st = layout_mesh(job, d, texel, err, err_len);
    if (st == TEXOPT_OK && moved && !jd->layout) { /* welded otherwise: left as they were */
        rep->not_disks += rep->unfolded;
        rep->unfolded = rep->tutte = rep->followed = 0;
        if (jd->share) { /* with every group as found, none released */
            texopt_texel_share_destroy(jd->share);
            jd->share = NULL;
            st = texopt_texel_share_create(&jd->share, jd->mesh, err, err_len);
        }
    }
    if (st == TEXOPT_OK && jd->layout && jd->share) {
        if (jd->paid)
            texopt_texel_share_paid(jd->share, jd->layout, jd->paid);
        texopt_texel_share_rebase(jd->share, jd->layout);
    }
    free(texel);
    return st;
}
