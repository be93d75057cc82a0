/* atomic_file.h - outputs written whole or not at all, without ever replacing what is not a
 * regular file.
 *
 * The output path is resolved first: symbolic links are followed to the file they name (the
 * link stays, its target is written). Then
 *   - a regular file, or a name that does not exist yet, is written to a temporary file beside
 *     it, flushed, synced and renamed over it: a crash or error never leaves a half-written file;
 *   - a character or block device, a FIFO or a Unix socket is written through directly (it
 *     cannot be replaced: /dev/null stays a device, a FIFO's reader gets the data). A FIFO with
 *     no reader is an error, not a wait; such outputs cannot be taken back after an error;
 *   - a directory is refused. */
#ifndef RAD_CORE_ATOMIC_FILE_H
#define RAD_CORE_ATOMIC_FILE_H

#include "core/context.h"

#include <stdio.h>

typedef struct rad_atomic_file {
    rad_context *ctx;
    FILE *file;      /* write here */
    char *path;      /* the name as given (for messages) */
    char *target;    /* the file written: the path with its symbolic links followed */
    char *temporary; /* the name while writing; NULL when writing through */
    int direct;      /* nonzero when writing straight into a device, FIFO or socket */
} rad_atomic_file;

/* Opens the output: a temporary file in the target's directory, or the special file itself.
 * Fails with a clear message ("PATH: cannot write: REASON", "PATH: is a directory, not a
 * file") when it cannot be written. */
rad_status rad_atomic_open(rad_context *ctx, const char *path, rad_atomic_file *out);

/* Checks, before long work, that `path` could be opened as rad_atomic_open would, with the same
 * messages, without touching it: a temporary file is made and removed beside a regular target;
 * a special file is only checked for write permission (opening a FIFO would end its reader). */
rad_status rad_atomic_check(rad_context *ctx, const char *path);

/* Flushes, checks for write errors and renames into place (or closes the special file); always
 * releases the file. `direct` stays readable afterwards. */
rad_status rad_atomic_commit(rad_atomic_file *file);

/* Drops the temporary file (after an error). Safe on a file that failed to open. */
void rad_atomic_abandon(rad_atomic_file *file);

/* The whole of `size` bytes to `path` by the rules above. */
rad_status rad_atomic_write(rad_context *ctx, const char *path, const void *data, size_t size);

#endif
