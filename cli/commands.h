/* commands.h - the subcommands of the `texopt` command line, one file each (cmd_*.c).
 *
 * Each takes the arguments after its own name and returns the process exit code:
 * 0 success, 1 the engine refused or failed (message on stderr), 2 usage error,
 * 3 canceled (SIGINT/SIGTERM). */
#ifndef TEXOPT_CLI_COMMANDS_H
#define TEXOPT_CLI_COMMANDS_H

enum { EXIT_OK = 0, EXIT_ENGINE = 1, EXIT_USAGE = 2, EXIT_CANCELED = 3 };

typedef struct cli_command {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv);
} cli_command;

/* int cmd_NAME(int argc, char **argv); one line per cmd_*.c */
int cmd_info(int argc, char **argv);
int cmd_evaluate(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_optimize(int argc, char **argv);

#endif
