/* main.c - `texopt COMMAND ...`: dispatches to the subcommands of commands.h. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "texopt.h"

static const cli_command commands[] = {
    /* {"name", "summary", cmd_name}, one line per cmd_*.c */
    {"compare", "q_r-c_r curves of several layout methods, JSON and HTML report", cmd_compare},
    {"evaluate", "whole-mesh perceptual loss and cost of OUT against IN", cmd_evaluate},
    {"info", "describe a model's texture domains and UV layout as JSON", cmd_info},
    {"optimize", "optimise a model's UV layout and re-bake its textures to a budget", cmd_optimize},
    {NULL, NULL, NULL},
};

static void print_usage(FILE *out)
{
    fprintf(out, "usage: texopt COMMAND [ARGS]\n\ncommands:\n");
    for (size_t i = 0; commands[i].name; i++)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n`texopt COMMAND --help` describes one command.\n"
                 "exit codes: 0 success, 1 refused or failed, 2 usage error, 3 canceled\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_usage(stderr);
        return EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        print_usage(stdout);
        return EXIT_OK;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("texopt %s (%s)\n", texopt_version(), texopt_build_revision());
        return EXIT_OK;
    }
    texopt_limit_library_threads();
    for (size_t i = 0; commands[i].name; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 2, argv + 2);
    fprintf(stderr, "texopt: unknown command '%s'\n\n", argv[1]);
    print_usage(stderr);
    return EXIT_USAGE;
}
