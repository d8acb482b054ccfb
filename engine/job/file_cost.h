/* file_cost.h - what a written model file costs, measured one way for the job's statistics
 * and for `texopt info` (issue 37: the numbers texopt reports are those of the file it wrote).
 *
 * Covered texels and packing of a domain are coverage.h's on the file's own layout: the
 * mesh of the UVs as the file stores them (floats, in the frame of its images), a triangle
 * covering nothing when that layout makes it degenerate (mesh.h). Texture pixels are the sum
 * of width x height over the images the file holds, texture bytes their encoded sizes. The
 * output's distortion metrics are distortion.h's on that same layout.
 * Does not: judge the layout (layout_check.h) or write anything. */
#ifndef TEXOPT_FILE_COST_H
#define TEXOPT_FILE_COST_H

#include <stdint.h>

#include "model.h"
#include "stats.h"
#include "status.h"

typedef struct texopt_file_cost {
    uint64_t texture_pixels; /* sum of width x height over the model's images */
    uint64_t texture_bytes;  /* sum of their encoded sizes in the file */
} texopt_file_cost;

/* The model's texture pixels and bytes (images the loader did not read count 0). */
void texopt_file_cost_of_model(const texopt_model *model, texopt_file_cost *out);

/* Loads the .glb at path (image headers only) and writes what it costs into the job's
 * statistics: per domain that had an input cost, cost_output, relative_cost and
 * packing_efficiency as `texopt info` measures them on the file (and distortion_out where
 * the job measured a distortion); the file's texture pixels,
 * texture bytes and bytes. Fails when the file's domains are not the job's. */
texopt_status texopt_file_cost_record(const char *path, texopt_job_stats *stats, char *err, size_t err_len);

#endif
