/* upload.h - a job's request body, streamed to its directory as it arrives.
 *
 * Two forms (after systemd-journal-remote: the body goes to its destination chunk by chunk,
 * nothing is held in memory but the small `params` part):
 *  - raw: the body is the .glb (Content-Type model/gltf-binary), written to input/model.glb;
 *  - multipart/form-data (through libmicrohttpd's post processor): the file part named
 *    `model` is the .glb or .gltf; every other file part (any field name) is a file the
 *    model refers to (.bin, images), stored under its file name, which may contain
 *    sub-directories ("textures/a.png") but no "..", no absolute path, no backslash;
 *    the non-file part `params` is the JSON parameters (at most 64 KiB).
 * Every file is fsynced when complete, so an accepted job's input survives a crash.
 * Does not: validate the model (model_check.h) or the params (params_json.h). */
#ifndef TEXOPT_API_UPLOAD_H
#define TEXOPT_API_UPLOAD_H

#include <stddef.h>
#include <stdint.h>

struct MHD_Connection;
typedef struct api_upload api_upload;

#define API_UPLOAD_MAX_PARAMS 65536

/* Starts an upload into dir/input/. multipart selects the form (the connection's headers
 * give the boundary). limit is the largest body accepted. NULL with a problem filled
 * (status, slug, detail) on failure. */
api_upload *api_upload_begin(const char *dir, int multipart, struct MHD_Connection *connection, uint64_t limit,
                             int *status, const char **slug, char *detail, size_t detail_len);

/* Feeds the next body bytes. Returns 0, or -1 once the upload failed (see api_upload_error). */
int api_upload_feed(api_upload *u, const char *data, size_t size);

/* Ends the body: closes and syncs the files, checks a model part arrived. 0 or -1. */
int api_upload_finish(api_upload *u);

/* The failure: HTTP status, problem slug, detail. Status 0 when none. */
int api_upload_error(const api_upload *u, const char **slug, const char **detail);

/* Bytes of the body as received (the multipart envelope included), and of the files stored
 * from it (the model and its files: what the job's upload_bytes reports). */
uint64_t api_upload_bytes(const api_upload *u);
uint64_t api_upload_file_bytes(const api_upload *u);
/* fingerprint.h digest of the stored files' names and bytes, in the order they came. */
uint64_t api_upload_digest(const api_upload *u);
/* The model file relative to dir ("input/model.glb") and its client-side name. */
const char *api_upload_model_rel(const api_upload *u);
const char *api_upload_model_name(const api_upload *u);
/* The params part, NUL-terminated, or NULL when none came. */
const char *api_upload_params(const api_upload *u, size_t *len);

void api_upload_destroy(api_upload *u); /* accepts NULL; leaves the files */

/* Whether a client-supplied relative file name is safe to create under a directory:
 * non-empty, at most 200 bytes, relative, no "." / ".." / empty components, no backslash,
 * no control characters. */
int api_upload_safe_name(const char *name);

#endif
