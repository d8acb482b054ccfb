/* texopt.h - the texopt engine's one public header.
 *
 * texopt computes a new UV layout for a textured glTF 2.0 model that gives each triangle as
 * many texels as its perceived detail needs (Sun et al. 2022, "Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen"), re-bakes the textures into it and
 * saves the result as .glb. The command line (cli/) and the service (api/, server/) use the
 * engine through this header alone; everything else under engine/ is internal and may change.
 *
 * Conventions, for every function declared here:
 *   - errors are values: a texopt_status, and a message written into the caller's err buffer
 *     of err_len bytes (which may be NULL); nothing exits, nothing prints;
 *   - the caller owns what it passes in; every *_create / *_load has its *_destroy, which
 *     accepts NULL;
 *   - no globals: a job carries its own state, so jobs run side by side in one process;
 *   - progress and cancellation go through a texopt_monitor the caller owns.
 *
 * What it offers, in the order a job uses it:
 *   status.h          texopt_status and texopt_strerror
 *   monitor.h         texopt_progress, texopt_monitor: progress reports and the cancel flag
 *   params.h          texopt_params: method, budget (relative cost, texture size or target
 *                     loss) and the knobs of the stages; texopt_params_resolve / _validate
 *   pipeline.h        the job: texopt_optimize_file (load, lay out, re-bake, save, statistics
 *                     JSON), or texopt_job_create + texopt_job_write for several budgets of
 *                     one model
 *   gltf_io.h         texopt_model_load / texopt_model_destroy (model.h: the loaded model),
 *                     for the calls below that read a model
 *   info.h            texopt_info_json: what a model's texture domains look like
 *   evaluate.h        texopt_evaluate: the whole-mesh loss q of one layout against another,
 *                     texopt_evaluate_cost
 *   map_check.h       texopt_map_evaluate: q of every map a material binds, and lit
 *   compare.h         texopt_compare: q against relative cost for several methods;
 *   report.h          texopt_report_write_html: its self-contained HTML report
 *   json_depth.h      texopt_json_check_depth: a JSON text's nesting, checked before parsing
 *   build_info.h      texopt_version, texopt_build_revision
 *   library_threads.h texopt_limit_library_threads: thread settings of the linked libraries
 *
 * The engine's rooms, in pipeline order, are described in docs/architecture.md. */
#ifndef TEXOPT_H
#define TEXOPT_H

#include "build_info.h"
#include "compare.h"
#include "evaluate.h"
#include "gltf_io.h"
#include "info.h"
#include "json_depth.h"
#include "library_threads.h"
#include "map_check.h"
#include "model.h"
#include "monitor.h"
#include "params.h"
#include "pipeline.h"
#include "report.h"
#include "status.h"

#endif
