/* report.h - the self-contained HTML report of a comparison (compare.h).
 *
 * What Sun et al. 2022 ("Efficient Texture Parameterization Driven by Perceptual-Loss-on-
 * Screen", section 5) shows to argue that a layout is worth it, for one model:
 *   - the q_r-c_r plot of every method (inline SVG, one polyline per method, class "curve",
 *     data-method="name"), and the numbers as a table;
 *   - before/after renders from three of the 20 evaluation views, the input next to every
 *     method's output at the same relative cost (the showcase cost): equal pixel budget.
 *     They show what q measured (evaluate.h texopt_evaluate_render: the texture's texels, a
 *     normal map turned back to the input's frame, or the lit render in grey). The views
 *     are those with the largest loss (mean over the showcases' per-view GMSD, each shown
 *     under its render), or views 0, 7 and 13 when no showcase was measured;
 *   - per texture domain (the first 8), every method's new texture of that measure (base
 *     colour for lit; thumbnail) and its UV layout coloured by per-triangle loss (mean absolute
 *     luma error over the views, evaluate.h) and by lambda1 lambda2 (new texel area / input
 *     texel area: blue shrunk, white kept, red grown).
 * Images are PNG (io/image_io.h) inlined as base64 data URIs; nothing is fetched from the
 * network, so the file can be mailed or archived as is.
 *
 * Does not: run anything (compare.c does) or write JSON. */
#ifndef TEXOPT_REPORT_H
#define TEXOPT_REPORT_H

#include <stddef.h>

#include "compare.h"
#include "status.h"

typedef struct texopt_report_options {
    const char *title;  /* shown as the heading (e.g. the model's file name); NULL -> "texopt" */
    int render_side;    /* before/after render side in pixels; 0 -> min(512, evaluation side) */
    int thumbnail_side; /* texture and UV map side; 0 -> 256 */
} texopt_report_options;

/* Writes the HTML report of r to path (temp + fsync + rename). opt may be NULL. */
texopt_status texopt_report_write_html(const texopt_compare_result *r, const texopt_report_options *opt,
                                       const char *path, char *err, size_t err_len);

/* The HTML as a malloc'ed NUL-terminated string (*html, freed with free()). */
texopt_status texopt_report_html(const texopt_compare_result *r, const texopt_report_options *opt, char **html,
                                 char *err, size_t err_len);

#endif
