/* atomic_file.h - outputs written whole or not at all: write to a temporary file beside the
 * target, flush, then rename over it. A crash or error never leaves a half-written file. */
#ifndef RAD_IO_ATOMIC_FILE_H
#define RAD_IO_ATOMIC_FILE_H

#include "core/context.h"

#include <stdio.h>

typedef struct rad_atomic_file {
    rad_context *ctx;
    FILE *file;      /* write here */
    char *path;      /* the final name */
    char *temporary; /* the name while writing */
} rad_atomic_file;

/* Opens a temporary file in the target's directory. Fails with a clear message when the
 * directory cannot be written. */
rad_status rad_atomic_open(rad_context *ctx, const char *path, rad_atomic_file *out);

/* Flushes, checks for write errors and renames into place; always releases the file. */
rad_status rad_atomic_commit(rad_atomic_file *file);

/* Drops the temporary file (after an error). Safe on a file that failed to open. */
void rad_atomic_abandon(rad_atomic_file *file);

#endif
