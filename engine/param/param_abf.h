/* param_abf.h - linear angle based flattening (LABF, Zayer, Levy and Seidel 2007) with the
 * least-squares angle reconstruction of the lecture.
 *
 * Target angles beta are the 3D corner angles, scaled at each interior vertex to sum 2 pi.
 * The planar angles theta = beta + phi minimise sum (phi / beta)^2 subject to the three ABF
 * conditions (triangle sums pi, interior vertex sums 2 pi, and the sine condition at every
 * interior vertex, linearised around beta as LABF does): phi = D^-1 A^T (A D^-1 A^T)^-1 b.
 * The layout is then the least-squares fit of e_ik = (sin theta_j / sin theta_k) R(theta_i)
 * e_ij over every corner of every triangle, with the two vertices of one edge pinned at its
 * 3D length. A developable chart keeps its 3D angles exactly and is laid out isometrically.
 * It does not run the nonlinear ABF++ Newton iterations. */
#ifndef TEXOPT_PARAM_ABF_H
#define TEXOPT_PARAM_ABF_H

#include "param_chart.h"
#include "status.h"

typedef struct texopt_abf_report {
    double max_angle_change; /* max |theta - beta| over corners, radians */
    double max_angle_error;  /* max |layout angle - theta| over corners, radians */
} texopt_abf_report;

/* Writes 2 doubles per vertex into uv (caller-owned, 2 * vertex_count); report may be NULL.
 * Fails with TEXOPT_E_NUMERIC when a planar angle comes out non-positive. */
texopt_status texopt_param_abf(const texopt_param_chart *chart, double *uv, texopt_abf_report *report, char *err,
                               size_t err_len);

#endif
