/* cancel.h - SIGINT and SIGTERM raise the cancel flag the engine checks at its checkpoints,
 * so an interrupted command stops cleanly (exit 3) instead of dying with a partial file. */
#ifndef TEXOPT_CLI_CANCEL_H
#define TEXOPT_CLI_CANCEL_H

#include <stdatomic.h>

/* Installs the handlers and returns the flag they raise (for texopt_monitor.cancel). */
const atomic_int *cli_cancel_on_signals(void);

#endif
