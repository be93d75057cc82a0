/* atomic_file.c - write-then-rename outputs, written through for special files (atomic_file.h). */
#include "core/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

enum { MAX_LINKS = 40 }; /* as the kernel's own limit on a chain of symbolic links */

/* The file `path` names once its symbolic links are followed (the final component only; the
 * directories on the way are the kernel's business). A dangling link gives the name the link
 * points at, so the file is created there, as `>` in a shell would. NULL on a loop (errno
 * ELOOP) or out of memory (ENOMEM). */
static char *follow_links(rad_context *ctx, const char *path) {
    char *current = rad_strdup(ctx, path);
    for (int hops = 0; current && hops <= MAX_LINKS; ++hops) {
        struct stat st;
        if (lstat(current, &st) != 0 || !S_ISLNK(st.st_mode)) return current;
        char target[PATH_MAX];
        ssize_t length = readlink(current, target, sizeof target - 1);
        if (length < 0) return current;
        target[length] = '\0';
        const char *slash = strrchr(current, '/');
        size_t directory = target[0] == '/' || !slash ? 0 : (size_t)(slash - current) + 1;
        char *next = rad_alloc(ctx, directory + (size_t)length + 1, 1);
        if (!next) {
            rad_free(ctx, current);
            errno = ENOMEM;
            return NULL;
        }
        memcpy(next, current, directory);
        memcpy(next + directory, target, (size_t)length + 1);
        rad_free(ctx, current);
        current = next;
    }
    if (current) {
        rad_free(ctx, current);
        errno = ELOOP;
    } else {
        errno = ENOMEM;
    }
    return NULL;
}

static int is_special(mode_t mode) {
    return S_ISCHR(mode) || S_ISBLK(mode) || S_ISFIFO(mode) || S_ISSOCK(mode);
}

/* Opens a device, FIFO or socket for writing: never blocks (a FIFO with no reader is ENXIO),
 * then blocking writes as usual. Returns the descriptor or -1 with errno set. */
static int open_special(const char *target, mode_t mode) {
    int fd;
    if (S_ISSOCK(mode)) {
        struct sockaddr_un address = {.sun_family = AF_UNIX};
        if (strlen(target) >= sizeof address.sun_path) {
            errno = ENAMETOOLONG;
            return -1;
        }
        strcpy(address.sun_path, target);
        fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (fd >= 0 && connect(fd, (struct sockaddr *)&address, sizeof address) != 0) {
            int saved = errno;
            close(fd);
            errno = saved;
            return -1;
        }
        return fd;
    }
    fd = open(target, O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd >= 0) {
        int flags = fcntl(fd, F_GETFL);
        if (flags >= 0) fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    }
    return fd;
}

static rad_status cannot_write(rad_context *ctx, const char *path, int error) {
    if (error == ENXIO)
        return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot write: no process is reading it", path);
    return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot write: %s", path, strerror(error));
}

/* mkstemp makes the file 0600; an output gets what a plain fopen would give it (0666 less the
 * umask; reading the umask means setting it, and it is set straight back), or the mode of the
 * file it replaces. */
static void give_permissions(int fd, const struct stat *replaced) {
    if (replaced) {
        fchmod(fd, replaced->st_mode & 07777);
        return;
    }
    mode_t mask = umask(0077);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
}

/* What the target is: 0 and *st filled when it exists, 1 when it does not (a new file),
 * or a failure already reported. */
static rad_status resolve(rad_context *ctx, const char *path, char **target, struct stat *st,
                          int *exists) {
    *target = NULL;
    if (!path || !*path) return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "empty output path");
    *target = follow_links(ctx, path);
    if (!*target) {
        if (errno == ENOMEM) return RAD_ERROR_NO_MEMORY;
        return cannot_write(ctx, path, errno);
    }
    *exists = stat(*target, st) == 0;
    if (*exists && S_ISDIR(st->st_mode))
        return rad_fail(ctx, RAD_ERROR_IO, "%s: is a directory, not a file", path);
    return RAD_OK;
}

rad_status rad_atomic_open(rad_context *ctx, const char *path, rad_atomic_file *out) {
    memset(out, 0, sizeof *out);
    out->ctx = ctx;
    struct stat st;
    int exists = 0;
    rad_status status = resolve(ctx, path, &out->target, &st, &exists);
    out->path = status ? NULL : rad_strdup(ctx, path);
    if (!status && !out->path) status = RAD_ERROR_NO_MEMORY;
    if (status) {
        rad_atomic_abandon(out);
        return status;
    }
    int fd;
    if (exists && is_special(st.st_mode)) {
        out->direct = 1;
        fd = open_special(out->target, st.st_mode);
    } else {
        /* Same directory as the target, so the rename stays on one file system. */
        size_t size = strlen(out->target) + 32;
        out->temporary = rad_alloc(ctx, size, 1);
        if (!out->temporary) {
            rad_atomic_abandon(out);
            return RAD_ERROR_NO_MEMORY;
        }
        snprintf(out->temporary, size, "%s.tmp-XXXXXX", out->target);
        fd = mkstemp(out->temporary);
        if (fd < 0) out->temporary[0] = '\0';
        else give_permissions(fd, exists && S_ISREG(st.st_mode) ? &st : NULL);
    }
    if (fd < 0) {
        status = cannot_write(ctx, path, errno);
        rad_atomic_abandon(out);
        return status;
    }
    out->file = fdopen(fd, "wb");
    if (!out->file) {
        int saved = errno;
        close(fd);
        rad_atomic_abandon(out);
        return cannot_write(ctx, path, saved);
    }
    return RAD_OK;
}

rad_status rad_atomic_check(rad_context *ctx, const char *path) {
    char *target;
    struct stat st;
    int exists = 0;
    rad_status status = resolve(ctx, path, &target, &st, &exists);
    if (!status && exists && is_special(st.st_mode)) {
        if (access(target, W_OK) != 0) status = cannot_write(ctx, path, errno);
    } else if (!status) {
        rad_atomic_file probe;
        status = rad_atomic_open(ctx, path, &probe);
        if (!status) rad_atomic_abandon(&probe);
    }
    rad_free(ctx, target);
    return status;
}

rad_status rad_atomic_commit(rad_atomic_file *f) {
    rad_status status = RAD_OK;
    if (!f->file) return rad_fail(f->ctx, RAD_ERROR_IO, "output file is not open");
    errno = 0;
    int failed = ferror(f->file) || fflush(f->file) != 0;
    /* Devices and FIFOs have nothing to sync (fsync fails on them with EINVAL). */
    if (!failed && !f->direct) failed = fsync(fileno(f->file)) != 0;
    int saved = errno;
    if (failed && !saved && !f->direct) {
        /* stdio kept no errno from the write that failed: one byte more to the temporary
         * (removed below) gives the reason, such as ENOSPC on a full disk. */
        if (write(fileno(f->file), "", 1) < 0) saved = errno;
    }
    if (fclose(f->file) != 0 && !failed) {
        failed = 1;
        saved = errno;
    }
    f->file = NULL;
    if (failed) {
        status = rad_fail(f->ctx, RAD_ERROR_IO, "%s: write failed: %s", f->path,
                          saved ? strerror(saved) : "write error");
    } else if (!f->direct && rename(f->temporary, f->target) != 0) {
        status = cannot_write(f->ctx, f->path, errno);
    } else if (!f->direct) {
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
    rad_free(f->ctx, f->target);
    rad_free(f->ctx, f->path);
    f->temporary = f->target = f->path = NULL;
}

rad_status rad_atomic_write(rad_context *ctx, const char *path, const void *data, size_t size) {
    rad_atomic_file file;
    rad_status status = rad_atomic_open(ctx, path, &file);
    if (status) return status;
    if (size) fwrite(data, 1, size, file.file); /* a short write is found by the commit */
    return rad_atomic_commit(&file);
}

rad_status rad_output_check(rad_context *ctx, const char *path) {
    if (!ctx) return RAD_ERROR_INVALID_ARGUMENT;
    return rad_atomic_check(ctx, path);
}

rad_status rad_output_write(rad_context *ctx, const char *path, const void *data, size_t size) {
    if (!ctx || (size && !data)) return RAD_ERROR_INVALID_ARGUMENT;
    return rad_atomic_write(ctx, path, data, size);
}
