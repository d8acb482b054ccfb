/* status.h - the engine's error values.
 *
 * Every engine function that can fail returns a texopt_status and, when given one, fills
 * a caller-owned message buffer (char *err, size_t err_len; either may be NULL/0) with a
 * sentence naming the offending element ("accessor 3: index 812 past vertex count 800").
 * Nothing in the engine prints or exits. */
#ifndef TEXOPT_STATUS_H
#define TEXOPT_STATUS_H

#include <stddef.h>

typedef enum texopt_status {
    TEXOPT_OK = 0,
    TEXOPT_E_INVALID_ARGUMENT, /* the caller passed a bad parameter */
    TEXOPT_E_IO,               /* a file could not be read or written (missing, disk full) */
    TEXOPT_E_MALFORMED,        /* the input is not a valid file of its kind */
    TEXOPT_E_UNSUPPORTED,      /* valid input texopt cannot work on (no UVs, no texture, ...) */
    TEXOPT_E_LIMIT,            /* the input exceeds a configured size limit */
    TEXOPT_E_NOMEM,            /* an allocation failed */
    TEXOPT_E_CANCELED,         /* the caller's cancel flag was raised */
    TEXOPT_E_NUMERIC,          /* a solve failed or produced non-finite values */
    TEXOPT_E_RENDER,           /* offscreen rendering failed */
    TEXOPT_E_INTERNAL,         /* a broken invariant: a bug in texopt */
    TEXOPT_STATUS_COUNT
} texopt_status;

/* A short constant name for a status ("malformed input"); never NULL. */
const char *texopt_strerror(texopt_status status);

/* Formats a message into err (when err is not NULL) and returns status, so that failures
 * read `return texopt_fail(err, err_len, TEXOPT_E_IO, "cannot open %s", path);`. */
texopt_status texopt_fail(char *err, size_t err_len, texopt_status status, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
