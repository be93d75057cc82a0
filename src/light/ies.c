/* ies.c - IES LM-63 photometric files (IESNA LM-63-1986/1991/1995/2002, "IES standard file
 * format for the electronic transfer of photometric data"): the candela distribution of a
 * luminaire on a grid of angles, read into a rad_ies_profile (lights.h) and interpolated.
 *
 * The file: an optional "IESNA:LM-63-..." line, keyword lines ("[TEST] ..."), a TILT= line,
 * then numbers separated by blanks or commas across lines:
 *   lamps, lumens per lamp, candela multiplier, vertical count, horizontal count,
 *   photometric type (1 = C, the only one read), units, width, length, height,
 *   ballast factor, ballast-lamp factor, input watts,
 *   the vertical angles, the horizontal angles, and for each horizontal angle the candela at
 *   every vertical angle.
 * TILT=INCLUDE carries its table before the numbers (skipped: the tilt of the lamp in its
 * fitting is not modelled); TILT=<file> is refused. */
#include "light/lights.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define IES_MAX_ANGLES 100000
#define IES_MAX_VALUES 4000000
#define IES_MAX_FILE_BYTES (64u << 20)

typedef struct ies_reader {
    rad_context *ctx;
    const char *p, *end, *source;
    int line;
} ies_reader;

/* The next line (without its end) into [*start, *stop); its number, or zero at the end of the
 * text. r->line is always the line of r->p. */
static int next_line(ies_reader *r, const char **start, const char **stop) {
    if (r->p >= r->end) return 0;
    int line = r->line;
    *start = r->p;
    while (r->p < r->end && *r->p != '\n') ++r->p;
    *stop = r->p;
    if (*stop > *start && (*stop)[-1] == '\r') --*stop;
    if (r->p < r->end) {
        ++r->p;
        ++r->line;
    }
    return line;
}

/* The next number, blanks and commas between; fails with file:line naming `what`. */
static rad_status next_number(ies_reader *r, const char *what, double *out) {
    for (;;) {
        while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == ',' || *r->p == '\r' ||
                                 *r->p == '\n')) {
            if (*r->p == '\n') ++r->line;
            ++r->p;
        }
        if (r->p >= r->end) /* named by its last line, not the empty one after it */
            return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: the file ends where %s should be",
                            r->source, r->line > 1 && r->p[-1] == '\n' ? r->line - 1 : r->line,
                            what);
        break;
    }
    char word[64];
    size_t n = 0;
    while (r->p < r->end && !strchr(" \t,\r\n", *r->p)) {
        if (n + 1 < sizeof word) word[n++] = *r->p;
        ++r->p;
    }
    word[n] = '\0';
    char *stop = NULL;
    double value = strtod(word, &stop);
    if (stop == word || *stop != '\0' || !isfinite(value))
        return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: %s should be a finite number, not '%s'",
                        r->source, r->line, what, word);
    *out = value;
    return RAD_OK;
}

/* A count in [1, limit]. */
static rad_status next_count(ies_reader *r, const char *what, size_t limit, size_t *out) {
    double value;
    rad_status status = next_number(r, what, &value);
    if (status) return status;
    if (!(value >= 1 && value <= (double)limit && value == floor(value)))
        return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: %s must be a whole number from 1 to %zu, "
                        "not %g", r->source, r->line, what, limit, value);
    *out = (size_t)value;
    return RAD_OK;
}

/* `count` ascending angles within [lo, hi]. */
static rad_status read_angles(ies_reader *r, const char *what, double lo, double hi, double *angles,
                              size_t count) {
    for (size_t i = 0; i < count; ++i) {
        rad_status status = next_number(r, what, &angles[i]);
        if (status) return status;
        if (angles[i] < lo || angles[i] > hi)
            return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: %s %g is outside %g..%g degrees",
                            r->source, r->line, what, angles[i], lo, hi);
        if (i > 0 && !(angles[i] > angles[i - 1]))
            return rad_fail(r->ctx, RAD_ERROR_PARSE, "%s:%d: %s must increase (%g after %g)",
                            r->source, r->line, what, angles[i], angles[i - 1]);
    }
    return RAD_OK;
}

void rad_ies_free(rad_context *ctx, rad_ies_profile *profile) {
    if (!profile) return;
    rad_free(ctx, profile->vertical);
    rad_free(ctx, profile->horizontal);
    rad_free(ctx, profile->candela);
    rad_free(ctx, profile);
}

static rad_status parse(ies_reader *r, rad_ies_profile *profile) {
    rad_context *ctx = r->ctx;
    /* Header lines up to TILT=. */
    const char *start, *stop;
    int tilt = 0, line, last = 1;
    while ((line = next_line(r, &start, &stop))) {
        last = line;
        if (stop - start >= 5 && strncmp(start, "TILT=", 5) == 0) {
            const char *value = start + 5;
            size_t length = (size_t)(stop - value);
            while (length && (value[length - 1] == ' ' || value[length - 1] == '\t')) --length;
            if (length == 4 && strncmp(value, "NONE", 4) == 0) {
                tilt = 1;
            } else if (length == 7 && strncmp(value, "INCLUDE", 7) == 0) {
                tilt = 2;
            } else {
                return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: TILT=%.*s: tilt files are not "
                                "read; use TILT=NONE or TILT=INCLUDE", r->source, line,
                                (int)(length > 60 ? 60 : length), value);
            }
            break;
        }
    }
    if (!tilt)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: no TILT= line: not an IES LM-63 file",
                        r->source, last);
    rad_status status = RAD_OK;
    double value;
    if (tilt == 2) {
        /* Lamp-to-luminaire geometry, then a count and that many angles and factors. */
        size_t pairs = 0;
        if ((status = next_number(r, "the tilt geometry", &value))) return status;
        if ((status = next_count(r, "the number of tilt angles", IES_MAX_ANGLES, &pairs)))
            return status;
        for (size_t i = 0; i < 2 * pairs; ++i)
            if ((status = next_number(r, i < pairs ? "a tilt angle" : "a tilt factor", &value)))
                return status;
    }
    double lamps, lumens, multiplier, type, units, size;
    if ((status = next_number(r, "the number of lamps", &lamps)) ||
        (status = next_number(r, "the lumens per lamp", &lumens)) ||
        (status = next_number(r, "the candela multiplier", &multiplier)))
        return status;
    if (!(multiplier > 0))
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: the candela multiplier must be > 0, not %g",
                        r->source, r->line, multiplier);
    if ((status = next_count(r, "the number of vertical angles", IES_MAX_ANGLES,
                             &profile->vertical_count)) ||
        (status = next_count(r, "the number of horizontal angles", IES_MAX_ANGLES,
                             &profile->horizontal_count)))
        return status;
    if (profile->vertical_count > IES_MAX_VALUES / profile->horizontal_count)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: %zu x %zu candela values are too many "
                        "(at most %d)", r->source, r->line, profile->vertical_count,
                        profile->horizontal_count, IES_MAX_VALUES);
    if ((status = next_number(r, "the photometric type", &type))) return status;
    if (type != 1)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: photometric type %g is not read (only type "
                        "1, C: vertical angles from the nadir)", r->source, r->line, type);
    if ((status = next_number(r, "the units type", &units))) return status;
    for (int i = 0; i < 3; ++i)
        if ((status = next_number(r, "a luminous opening size", &size))) return status;
    for (int i = 0; i < 3; ++i)
        if ((status = next_number(r, i == 0 ? "the ballast factor" : i == 1 ? "the ballast-lamp "
                                  "factor" : "the input watts", &value)))
            return status;
    size_t nv = profile->vertical_count, nh = profile->horizontal_count;
    profile->vertical = rad_alloc(ctx, nv, sizeof *profile->vertical);
    profile->horizontal = rad_alloc(ctx, nh, sizeof *profile->horizontal);
    profile->candela = rad_alloc(ctx, nv * nh, sizeof *profile->candela);
    if (!profile->vertical || !profile->horizontal || !profile->candela) return RAD_ERROR_NO_MEMORY;
    if ((status = read_angles(r, "a vertical angle", 0, 180, profile->vertical, nv)) ||
        (status = read_angles(r, "a horizontal angle", 0, 360, profile->horizontal, nh)))
        return status;
    profile->max_candela = 0;
    for (size_t i = 0; i < nv * nh; ++i) {
        if ((status = next_number(r, "a candela value", &value))) return status;
        if (value < 0)
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: a candela value must be >= 0, not %g",
                            r->source, r->line, value);
        profile->candela[i] = value * multiplier;
        if (!isfinite(profile->candela[i]))
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s:%d: candela %g times the multiplier %g is "
                            "not a finite number", r->source, r->line, value, multiplier);
        profile->max_candela = fmax(profile->max_candela, profile->candela[i]);
    }
    return RAD_OK;
}

rad_status rad_ies_parse(rad_context *ctx, const char *text, size_t length, const char *source,
                         rad_ies_profile **out) {
    *out = NULL;
    rad_ies_profile *profile = rad_alloc_zero(ctx, 1, sizeof *profile);
    if (!profile) return RAD_ERROR_NO_MEMORY;
    ies_reader r = {ctx, text, text + length, source ? source : "IES", 1};
    rad_status status = parse(&r, profile);
    if (status) {
        rad_ies_free(ctx, profile);
        return status;
    }
    *out = profile;
    return RAD_OK;
}

rad_status rad_ies_load(rad_context *ctx, const char *path, rad_ies_profile **out) {
    *out = NULL;
    struct stat info;
    if (stat(path, &info) != 0) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    if (!S_ISREG(info.st_mode)) return rad_fail(ctx, RAD_ERROR_IO, "%s: not a regular file", path);
    if (info.st_size > (off_t)IES_MAX_FILE_BYTES)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s:1: %lld bytes is too large for an IES file "
                        "(at most %u)", path, (long long)info.st_size, IES_MAX_FILE_BYTES);
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: %s", path, strerror(errno));
    size_t capacity = (size_t)info.st_size + 1;
    char *text = rad_alloc(ctx, capacity, 1);
    if (!text) {
        fclose(file);
        return RAD_ERROR_NO_MEMORY;
    }
    size_t length = fread(text, 1, capacity - 1, file);
    int failed = ferror(file);
    fclose(file);
    rad_status status = failed ? rad_fail(ctx, RAD_ERROR_IO, "%s: read error", path)
                               : rad_ies_parse(ctx, text, length, path, out);
    rad_free(ctx, text);
    return status;
}

/* Index i and weight t with angle = (1 - t) a[i] + t a[i + 1]; -1 outside [a[0], a[n-1]]. */
static long bracket(const double *a, size_t n, double angle, double *t) {
    if (angle < a[0] || angle > a[n - 1]) return -1;
    if (n == 1) {
        *t = 0;
        return 0;
    }
    size_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (a[mid] <= angle) lo = mid;
        else hi = mid;
    }
    *t = (angle - a[lo]) / (a[hi] - a[lo]);
    return (long)lo;
}

double rad_ies_candela(const rad_ies_profile *profile, double vertical, double horizontal) {
    size_t nv = profile->vertical_count, nh = profile->horizontal_count;
    /* The horizontal symmetries LM-63 gives by the last horizontal angle. */
    double h = fmod(horizontal, 360.0);
    if (h < 0) h += 360;
    double last = profile->horizontal[nh - 1];
    if (nh == 1) {
        h = profile->horizontal[0];
    } else if (last == 90) {
        if (h > 180) h = 360 - h;
        if (h > 90) h = 180 - h;
    } else if (last == 180) {
        if (h > 180) h = 360 - h;
    }
    double tv, th;
    long iv = bracket(profile->vertical, nv, vertical, &tv);
    if (iv < 0) return 0;
    long ih = bracket(profile->horizontal, nh, h, &th);
    if (ih < 0) {
        /* A full circle whose last angle is short of 360 closes on its first. */
        ih = (long)nh - 1;
        th = 0;
    }
    size_t v1 = (size_t)iv + (tv > 0 ? 1 : 0), h1 = (size_t)ih + (th > 0 ? 1 : 0);
    const double *c = profile->candela;
    double a = (1 - tv) * c[(size_t)ih * nv + (size_t)iv] + tv * c[(size_t)ih * nv + v1];
    double b = (1 - tv) * c[h1 * nv + (size_t)iv] + tv * c[h1 * nv + v1];
    return (1 - th) * a + th * b;
}
