/* numbers.h - strict parsing of numeric command-line arguments (the whole string, in range). */
#ifndef TEXOPT_CLI_NUMBERS_H
#define TEXOPT_CLI_NUMBERS_H

/* Parses a whole decimal integer in [lo, hi]; 0 on success, -1 otherwise. */
int cli_parse_int(const char *s, int lo, int hi, int *out);

/* Parses a whole decimal number in [lo, hi] (NaN never is); 0 on success, -1 otherwise. */
int cli_parse_double(const char *s, double lo, double hi, double *out);

#endif
