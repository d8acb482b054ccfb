/* atomic_file.h - writing a whole file so that readers see the old or the new file, never a
 * partial one.
 *
 * Does: write bytes to a temporary file in the destination's directory, fsync it, rename it
 * over the destination and fsync the directory. Does not: lock, append, or create
 * directories. Infrastructure for the outputs of Sun et al. 2022 ("Efficient Texture
 * Parameterization Driven by Perceptual-Loss-on-Screen"); implements no part of the method. */
#ifndef TEXOPT_ATOMIC_FILE_H
#define TEXOPT_ATOMIC_FILE_H

#include <stddef.h>

/* The engine's C headers carry no linkage guards; wrap them for the C++ shims. */
#ifdef __cplusplus
extern "C" {
#endif

#include "status.h"

/* Replaces the file at path with len bytes (bytes may be NULL when len is 0). On failure the
 * old file, if any, is untouched and no temporary file is left behind (TEXOPT_E_IO). */
texopt_status texopt_write_file_atomic(const char *path, const void *bytes, size_t len, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif
