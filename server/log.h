/* log.h - one structured line per event, key=value (logfmt), on stderr.
 *
 * Does: timestamps each line (RFC 3339, UTC, milliseconds) and writes it with one call so
 * lines from concurrent threads never interleave. Does not: buffer, rotate or filter;
 * the supervisor (systemd, docker) collects stderr. */
#ifndef TEXOPT_SERVER_LOG_H
#define TEXOPT_SERVER_LOG_H

#include <stddef.h>

/* Writes "ts=... " followed by the formatted fields and a newline. */
void log_event(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Copies text into out as a logfmt value: quoted, with quotes, backslashes and control
 * characters escaped, truncated to fit. Returns out. */
const char *log_quote(char *out, size_t out_len, const char *text);

#endif
