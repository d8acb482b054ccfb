/* pipeline.h - one whole job: load, optimise every texture domain, re-bake, save.
 *
 * The one entry point the command line and the service share. It knows the stages and their
 * order; it knows nothing of HTTP or terminals. */
#ifndef TEXOPT_PIPELINE_H
#define TEXOPT_PIPELINE_H

#include "monitor.h"
#include "params.h"
#include "status.h"

/* Optimises the model at input_path (.glb or .gltf) with params (resolved and validated
 * inside) and writes output_glb and, when stats_json is not NULL, the statistics as JSON.
 * Both are written to a temporary file, synced and renamed, so a failure or a kill never
 * leaves a partial file under the final name. */
texopt_status texopt_optimize_file(const char *input_path, const char *output_glb,
                                   const char *stats_json, const texopt_params *params,
                                   const texopt_monitor *monitor, char *err, size_t err_len);

#endif
