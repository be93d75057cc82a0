/* output_path.h - an output file must never be one of the command's inputs: writing it would
 * destroy the input (and, with temp + rename, silently replace it). */
#ifndef RAD_CLI_OUTPUT_PATH_H
#define RAD_CLI_OUTPUT_PATH_H

#include <stddef.h>

/* Prints a usage error and returns EXIT_USAGE when `output` is the same file as one of the
 * inputs (the same device and inode, so another spelling or a link counts too); 0 otherwise.
 * NULL outputs and inputs are skipped, as are inputs that are not files (built-in scene names). */
int cli_check_output_path(const char *command, const char *output, const char *const *inputs,
                          size_t input_count);

#endif
