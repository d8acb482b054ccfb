/* param_lscm.h - least squares conformal maps (Levy et al. 2002).
 *
 * Minimises, over the layout, the area-weighted squared violation of the Cauchy-Riemann
 * equations per triangle (the lecture's E_LSCM), with two far-apart boundary vertices pinned
 * to remove the similarity it is invariant under. The boundary is free. A planar chart is
 * reproduced up to a similarity. The layout may fold on strongly curved charts (LSCM does not guarantee a bijection); the caller
 * checks flips. */
#ifndef TEXOPT_PARAM_LSCM_H
#define TEXOPT_PARAM_LSCM_H

#include "param_chart.h"
#include "status.h"

/* Writes 2 doubles per vertex into uv (caller-owned, 2 * vertex_count); the layout is at the
 * chart's 3D scale (the pinned pair keeps its 3D distance). */
texopt_status texopt_param_lscm(const texopt_param_chart *chart, double *uv, char *err, size_t err_len);

#endif
