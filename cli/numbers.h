/* numbers.h - strict parsing of numeric command-line arguments (the whole string, in range). */
#ifndef TEXOPT_CLI_NUMBERS_H
#define TEXOPT_CLI_NUMBERS_H

#include <stdint.h>

/* Parses a whole decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int cli_parse_int(const char *s, int lo, int hi, int *out);

/* Parses a random seed: a whole decimal integer in [0, 2^53], the range the service's JSON
 * parameters take (server/params_json.c), so a seed that works in one front end works in all;
 * 0 on success, -1 otherwise. */
int cli_parse_seed(const char *s, uint64_t *out);

/* Parses a whole decimal number in [lo, hi] (NaN never is); 0 on success, -1 otherwise. */
int cli_parse_double(const char *s, double lo, double hi, double *out);

#endif
