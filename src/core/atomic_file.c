/* atomic_file.c - write-then-rename outputs (see atomic_file.h). */
#include "core/atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* mkstemp makes the file 0600; an output gets what a plain fopen would give it: 0666 less the
 * umask. (Reading the umask means setting it; it is set straight back.) */
static void give_default_permissions(int fd) {
    mode_t mask = umask(0077);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
}

rad_status rad_atomic_open(rad_context *ctx, const char *path, rad_atomic_file *out) {
    memset(out, 0, sizeof *out);
    out->ctx = ctx;
    if (!path || !*path) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "empty output path");
    size_t length = strlen(path);
    out->path = rad_strdup(ctx, path);
    out->temporary = rad_alloc(ctx, length + 32, 1);
    if (!out->path || !out->temporary) {
        rad_atomic_abandon(out);
        return RAD_ERROR_NO_MEMORY;
    }
    /* Same directory, so the rename stays on one file system. */
    snprintf(out->temporary, length + 32, "%s.tmp-XXXXXX", path);
    int fd = mkstemp(out->temporary);
    if (fd < 0) {
        rad_status status = rad_fail(ctx, RAD_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
        out->temporary[0] = '\0';
        rad_atomic_abandon(out);
        return status;
    }
    give_default_permissions(fd);
    out->file = fdopen(fd, "wb");
    if (!out->file) {
        close(fd);
        rad_status status = rad_fail(ctx, RAD_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
        rad_atomic_abandon(out);
        return status;
    }
    return RAD_OK;
}

rad_status rad_atomic_commit(rad_atomic_file *f) {
    rad_status status = RAD_OK;
    if (!f->file) return rad_fail(f->ctx, RAD_ERROR_IO, "output file is not open");
    int failed = ferror(f->file) || fflush(f->file) != 0 || fsync(fileno(f->file)) != 0;
    int saved = errno;
    if (fclose(f->file) != 0) failed = 1;
    f->file = NULL;
    if (failed) {
        status = rad_fail(f->ctx, RAD_ERROR_IO, "%s: write failed: %s", f->path, strerror(saved));
    } else if (rename(f->temporary, f->path) != 0) {
        status = rad_fail(f->ctx, RAD_ERROR_IO, "%s: cannot write: %s", f->path, strerror(errno));
    } else {
        f->temporary[0] = '\0'; /* renamed: nothing to remove */
    }
    rad_atomic_abandon(f);
    return status;
}

void rad_atomic_abandon(rad_atomic_file *f) {
    if (f->file) fclose(f->file);
    f->file = NULL;
    if (f->temporary && f->temporary[0]) unlink(f->temporary);
    rad_free(f->ctx, f->temporary);
    rad_free(f->ctx, f->path);
    f->temporary = NULL;
    f->path = NULL;
}
