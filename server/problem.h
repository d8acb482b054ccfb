/* problem.h - RFC 9457 problem details: the body of every error the service answers.
 *
 * Does: build the application/problem+json body ({type, title, status, detail, instance})
 * and map engine statuses to HTTP statuses. Does not: send anything (api/http.c does).
 * `type` is "urn:texopt:problem:<slug>", a stable identifier clients can switch on. */
#ifndef TEXOPT_API_PROBLEM_H
#define TEXOPT_API_PROBLEM_H

#include "texopt.h"

/* The standard reason phrase of an HTTP status ("Unprocessable Content"). */
const char *api_status_title(int status);

/* A new problem+json text (caller frees). instance may be NULL. NULL on allocation failure. */
char *api_problem_json(int status, const char *slug, const char *detail, const char *instance);

/* What an engine status means for a client's upload or job:
 * MALFORMED 400, IO 400 (a file the model needs is missing), INVALID_ARGUMENT 400,
 * LIMIT 413, UNSUPPORTED 422, CANCELED 409, anything else 500. */
int api_status_from_engine(texopt_status status);
/* The problem slug for an engine status ("malformed-model"). */
const char *api_slug_from_engine(texopt_status status);

#endif
