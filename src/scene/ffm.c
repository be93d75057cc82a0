/* ffm.c - the patch-system format: patches with area, reflectance and emission, and the form
 * factors between them (docs/formats.md).
 *
 *   patch NAME area A reflectance R [G B] emission E [G B]
 *   ff FROM TO VALUE     # fraction of the energy leaving FROM that arrives at TO
 */
#include "core/hash_index.h"
#include "scene/scene.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FFM_MAX_TOKENS 16
#define FFM_ROW_SUM_SLACK 1e-3

/* ------------------------------------------------------------------------------------------- */

typedef struct ffm_parser {
    rad_context *ctx;
    const char *source;
    int line;
    rad_scene *scene;
    size_t patch_capacity;
    rad_hash_index patch_names; /* name -> patch number */
    /* Form factors as read, before the matrix exists: (from, to, value, line). */
    struct ffm_entry { size_t from, to; double value; int line; } *entries;
    size_t entry_count, entry_capacity;
    rad_hash_index entry_pairs; /* (from, to) -> entry number */
} ffm_parser;

#define FFM_FAIL(p, ...) ffm_fail(p, __VA_ARGS__)

RAD_PRINTF(2, 3) static rad_status ffm_fail(ffm_parser *p, const char *format, ...) {
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return rad_fail(p->ctx, RAD_ERROR_PARSE, "%s:%d: %s", p->source, p->line, message);
}

/* A finite number, or a parse error naming what it was for. */
static rad_status parse_number(ffm_parser *p, const char *token, const char *what, double *out) {
    char *end;
    errno = 0;
    double value = strtod(token, &end);
    if (end == token || *end != '\0')
        return FFM_FAIL(p, "%s: '%s' is not a number", what, token);
    if (!isfinite(value) || errno == ERANGE)
        return FFM_FAIL(p, "%s: '%s' is not a finite number", what, token);
    *out = value;
    return RAD_OK;
}

static int is_number(const char *token) {
    char *end;
    strtod(token, &end);
    return end != token && *end == '\0';
}

/* Reads one grey value or three RGB values starting at tokens[*at]. */
static rad_status parse_color(ffm_parser *p, char **tokens, int count, int *at, const char *what,
                              double rgb[3]) {
    if (*at >= count) return FFM_FAIL(p, "%s needs a value", what);
    int values = 1;
    if (*at + 2 < count && is_number(tokens[*at + 1]) && is_number(tokens[*at + 2])) values = 3;
    for (int c = 0; c < values; ++c) {
        rad_status status = parse_number(p, tokens[*at + c], what, &rgb[c]);
        if (status) return status;
    }
    if (values == 1) rgb[1] = rgb[2] = rgb[0];
    *at += values;
    return RAD_OK;
}

static long find_patch(const ffm_parser *p, const char *name) {
    uint64_t hash = rad_hash_string(RAD_HASH_START, name);
    size_t slot = SIZE_MAX;
    for (size_t i; (i = rad_hash_index_next(&p->patch_names, hash, &slot)) != SIZE_MAX;)
        if (strcmp(p->scene->patches[i].name, name) == 0) return (long)i;
    return -1;
}

/* The entry already read for (from, to), or SIZE_MAX. */
static size_t find_entry(const ffm_parser *p, size_t from, size_t to) {
    size_t slot = SIZE_MAX;
    uint64_t hash = rad_hash_pair(from, to);
    for (size_t i; (i = rad_hash_index_next(&p->entry_pairs, hash, &slot)) != SIZE_MAX;)
        if (p->entries[i].from == from && p->entries[i].to == to) return i;
    return SIZE_MAX;
}

static rad_status parse_patch(ffm_parser *p, char **tokens, int count) {
    rad_scene *scene = p->scene;
    if (count < 2) return FFM_FAIL(p, "patch needs a name");
    const char *name = tokens[1];
    if (find_patch(p, name) >= 0) return FFM_FAIL(p, "duplicate patch name '%s'", name);
    rad_ffm_patch patch = {0};
    int have_area = 0, have_reflectance = 0;
    for (int at = 2; at < count;) {
        const char *key = tokens[at++];
        rad_status status;
        if (strcmp(key, "area") == 0) {
            if (at >= count) return FFM_FAIL(p, "area needs a value");
            if ((status = parse_number(p, tokens[at++], "area", &patch.area))) return status;
            if (patch.area <= 0) return FFM_FAIL(p, "area of '%s' must be positive", name);
            have_area = 1;
        } else if (strcmp(key, "reflectance") == 0) {
            if ((status = parse_color(p, tokens, count, &at, "reflectance", patch.reflectance)))
                return status;
            for (int c = 0; c < 3; ++c)
                if (patch.reflectance[c] < 0 || patch.reflectance[c] > 1)
                    return FFM_FAIL(p, "reflectance of '%s' must be in [0, 1]", name);
            have_reflectance = 1;
        } else if (strcmp(key, "emission") == 0) {
            if ((status = parse_color(p, tokens, count, &at, "emission", patch.emission)))
                return status;
            for (int c = 0; c < 3; ++c)
                if (patch.emission[c] < 0)
                    return FFM_FAIL(p, "emission of '%s' must not be negative", name);
        } else {
            return FFM_FAIL(p, "unknown patch property '%s' (expected area, reflectance, "
                               "emission)", key);
        }
    }
    if (!have_area) return FFM_FAIL(p, "patch '%s' needs an area", name);
    if (!have_reflectance) return FFM_FAIL(p, "patch '%s' needs a reflectance", name);
    if (scene->patch_count == p->patch_capacity) {
        size_t wanted = p->patch_capacity ? 2 * p->patch_capacity : 16;
        rad_ffm_patch *grown = rad_realloc(p->ctx, scene->patches, wanted, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        scene->patches = grown;
        p->patch_capacity = wanted;
    }
    patch.name = rad_strdup(p->ctx, name);
    if (!patch.name) return RAD_ERROR_NO_MEMORY;
    scene->patches[scene->patch_count++] = patch;
    return rad_hash_index_insert(p->ctx, &p->patch_names, rad_hash_string(RAD_HASH_START, name),
                                 scene->patch_count - 1);
}

static rad_status parse_ff(ffm_parser *p, char **tokens, int count) {
    if (count != 4) return FFM_FAIL(p, "expected 'ff FROM TO VALUE'");
    long from = find_patch(p, tokens[1]);
    if (from < 0) return FFM_FAIL(p, "unknown patch '%s' (patches come before ff lines)", tokens[1]);
    long to = find_patch(p, tokens[2]);
    if (to < 0) return FFM_FAIL(p, "unknown patch '%s' (patches come before ff lines)", tokens[2]);
    double value = 0;
    rad_status status = parse_number(p, tokens[3], "form factor", &value);
    if (status) return status;
    if (value < 0 || value > 1)
        return FFM_FAIL(p, "form factor %s -> %s must be in [0, 1], not %g", tokens[1], tokens[2],
                        value);
    size_t first = find_entry(p, (size_t)from, (size_t)to);
    if (first != SIZE_MAX)
        return FFM_FAIL(p, "duplicate form factor %s -> %s (first on line %d)", tokens[1],
                        tokens[2], p->entries[first].line);
    if (p->entry_count == p->entry_capacity) {
        size_t wanted = p->entry_capacity ? 2 * p->entry_capacity : 64;
        struct ffm_entry *grown = rad_realloc(p->ctx, p->entries, wanted, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        p->entries = grown;
        p->entry_capacity = wanted;
    }
    p->entries[p->entry_count++] = (struct ffm_entry){(size_t)from, (size_t)to, value, p->line};
    return rad_hash_index_insert(p->ctx, &p->entry_pairs, rad_hash_pair((uint64_t)from, (uint64_t)to),
                                 p->entry_count - 1);
}

/* Splits a line in place at white space; '#' starts a comment. */
static int tokenize(char *line, char **tokens) {
    int count = 0;
    char *comment = strchr(line, '#');
    if (comment) *comment = '\0';
    for (char *s = line; *s;) {
        while (*s && isspace((unsigned char)*s)) ++s;
        if (!*s) break;
        if (count == FFM_MAX_TOKENS) return -1;
        tokens[count++] = s;
        while (*s && !isspace((unsigned char)*s)) ++s;
        if (*s) *s++ = '\0';
    }
    return count;
}

static rad_status parse_lines(ffm_parser *p, char *text, size_t length) {
    char *tokens[FFM_MAX_TOKENS];
    char *cursor = text, *end = text + length;
    while (cursor < end) {
        char *newline = memchr(cursor, '\n', (size_t)(end - cursor));
        char *line_end = newline ? newline : end;
        *line_end = '\0';
        ++p->line;
        if (memchr(cursor, '\0', (size_t)(line_end - cursor)))
            return FFM_FAIL(p, "binary data (a NUL byte) in a text file");
        int count = tokenize(cursor, tokens);
        if (count < 0) return FFM_FAIL(p, "too many words on one line");
        rad_status status = RAD_OK;
        if (count == 0) {
        } else if (strcmp(tokens[0], "patch") == 0) {
            status = parse_patch(p, tokens, count);
        } else if (strcmp(tokens[0], "ff") == 0) {
            status = parse_ff(p, tokens, count);
        } else {
            status = FFM_FAIL(p, "unknown keyword '%s' (expected patch or ff)", tokens[0]);
        }
        if (status) return status;
        cursor = line_end + 1;
    }
    return RAD_OK;
}

/* Builds the dense matrix and checks what needs the whole file: rows that sum above 1. */
static rad_status finish(ffm_parser *p) {
    rad_scene *scene = p->scene;
    size_t n = scene->patch_count;
    if (n == 0) return rad_fail(p->ctx, RAD_ERROR_PARSE, "%s: no patches", p->source);
    rad_status status = rad_check_budget(p->ctx, 8.0 * (double)n * (double)n,
                                         "the form-factor matrix of the patch system");
    if (status) return status;
    scene->form_factors = rad_alloc_zero(p->ctx, n * n, sizeof(double));
    if (!scene->form_factors) return RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < p->entry_count; ++i)
        scene->form_factors[p->entries[i].from * n + p->entries[i].to] = p->entries[i].value;
    for (size_t i = 0; i < n; ++i) {
        double sum = 0;
        for (size_t j = 0; j < n; ++j) sum += scene->form_factors[i * n + j];
        if (sum > 1 + FFM_ROW_SUM_SLACK) {
            int line = 0;
            for (size_t k = 0; k < p->entry_count; ++k)
                if (p->entries[k].from == i) line = p->entries[k].line;
            return rad_fail(p->ctx, RAD_ERROR_PARSE,
                            "%s:%d: form factors leaving '%s' sum to %.6g, more than 1", p->source,
                            line, scene->patches[i].name, sum);
        }
    }
    int emits = 0, reflects_all = 0;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            if (scene->patches[i].emission[c] > 0) emits = 1;
            if (scene->patches[i].reflectance[c] >= 1) reflects_all = 1;
        }
    if (!emits) rad_warn(p->ctx, "%s: nothing emits light; every radiosity will be 0", p->source);
    if (reflects_all)
        rad_warn(p->ctx, "%s: a reflectance of 1 loses no energy; iterative solvers may not "
                         "converge", p->source);
    return RAD_OK;
}

rad_status rad_scene_parse_ffm(rad_context *ctx, const char *text, size_t length,
                               const char *source_name, rad_scene **out) {
    if (!ctx || !out || (!text && length)) return RAD_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    if (!source_name) source_name = "<text>";
    ffm_parser p = {.ctx = ctx, .source = source_name};
    char *copy = rad_alloc(ctx, length + 1, 1);
    if (!copy) return RAD_ERROR_NO_MEMORY;
    if (length) memcpy(copy, text, length);
    copy[length] = '\0';
    rad_status status = rad_scene_new(ctx, 0, source_name, &p.scene);
    if (!status) status = parse_lines(&p, copy, length);
    if (!status) status = finish(&p);
    rad_free(ctx, copy);
    rad_free(ctx, p.entries);
    rad_hash_index_free(ctx, &p.patch_names);
    rad_hash_index_free(ctx, &p.entry_pairs);
    if (status) {
        rad_scene_destroy(p.scene);
        return status;
    }
    *out = p.scene;
    return RAD_OK;
}
