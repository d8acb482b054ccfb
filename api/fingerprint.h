/* fingerprint.h - a 64-bit digest of what a job request asked for, so that a retry with the
 * same Idempotency-Key can be told from a different request that reuses the key.
 *
 * FNV-1a over the uploaded files (names and bytes, as stored: multipart boundaries, which
 * curl draws at random per request, do not count) and the resolved parameters. It detects
 * accidental reuse of a key; it is not a cryptographic hash and does not defend against a
 * client forging collisions with its own key. */
#ifndef TEXOPT_API_FINGERPRINT_H
#define TEXOPT_API_FINGERPRINT_H

#include <stddef.h>
#include <stdint.h>

#define FINGERPRINT_SEED 14695981039346656037ull

uint64_t fingerprint_mix(uint64_t h, const void *data, size_t len);

/* 16 lowercase hex digits and a NUL into out[17]. */
void fingerprint_hex(uint64_t h, char out[17]);

#endif
