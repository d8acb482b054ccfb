/* store_url.h - reading the --store setting (no database access; unit-tested alone).
 *
 * Does: tell the on-disk store ("" or unset) from a PostgreSQL URL (postgresql:// or
 * postgres://, as libpq takes them), and write a URL for the log with its password hidden.
 * Does not: check that the database answers (store_pg.c does, at start-up). */
#ifndef TEXOPT_SERVER_STORE_URL_H
#define TEXOPT_SERVER_STORE_URL_H

#include <stddef.h>

typedef enum store_url_kind_t { STORE_URL_DISK, STORE_URL_POSTGRES, STORE_URL_INVALID } store_url_kind_t;

store_url_kind_t store_url_kind(const char *url);

/* url with the password of its user-info (user:password@) replaced by "***". */
void store_url_redact(const char *url, char *out, size_t out_len);

#endif
