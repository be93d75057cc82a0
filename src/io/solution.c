/* solution.c - saving and loading solutions (docs/formats.md, "Solution files").
 *
 * Layout, little-endian throughout:
 *   0   8  magic "RADSOLN\n"
 *   8   4  version (1)
 *   12  4  solver that wrote it (rad_solver_kind)
 *   16  8  steps done (rounds or shots, summed over resumed runs)
 *   24  8  element count      32  8  patch count      40  8  surface count
 *   48  8  scene fingerprint  56  8  mesh fingerprint 64  8  form-factor fingerprint
 *   72 24  ambient term, 3 x float64
 *   96     per element: radiosity[3], unshot[3], float64 (48 bytes each)
 *   end 8  FNV-1a 64 of every byte before it
 * Files are written to a temporary and renamed into place (core/atomic_file.h): whole or not at
 * all. A load checks everything before it touches the system, so a refused file loses nothing. */
#include "io/solution.h"

#include "core/atomic_file.h"
#include "mesh/mesh.h"
#include "solve/hierarchical_view.h"
#include "solve/solver.h"
#include "system/solution_view.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

uint64_t rad_fnv1a(uint64_t hash, const void *bytes, size_t count) {
    const unsigned char *p = bytes;
    for (size_t i = 0; i < count; ++i) {
        hash ^= p[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

/* Hashing values in a fixed byte order, so fingerprints agree across machines. */
static uint64_t hash_u64(uint64_t hash, uint64_t v) {
    unsigned char b[8];
    rad_le_put_u64(b, v);
    return rad_fnv1a(hash, b, 8);
}
static uint64_t hash_f64(uint64_t hash, double v) {
    unsigned char b[8];
    rad_le_put_f64(b, v == 0 ? 0.0 : v); /* -0 and +0 alike */
    return rad_fnv1a(hash, b, 8);
}
/* Values that are sums over elements differ in the last bits between meshings of the same
 * scene: hash them at float precision. */
static uint64_t hash_f32(uint64_t hash, double v) {
    float f = (float)v;
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    unsigned char b[4];
    rad_le_put_u32(b, f == 0 ? 0u : bits);
    return rad_fnv1a(hash, b, 4);
}

/* ------------------------------------------------------------------------------------------- */

rad_status rad_solution_fingerprint_compute(rad_system *s, rad_solution_fingerprint *out) {
    /* Scene: surface names and materials, whatever the meshing (not areas: a non-planar quad's
     * area depends on how finely it is cut). Geometry is in the mesh fingerprint. */
    uint64_t h = hash_u64(RAD_FNV1A_START, s->surface_count);
    rad_rgb *reflectance = rad_alloc(s->ctx, s->surface_count, sizeof *reflectance);
    rad_rgb *emission = rad_alloc(s->ctx, s->surface_count, sizeof *emission);
    if (!reflectance || !emission) {
        rad_free(s->ctx, reflectance);
        rad_free(s->ctx, emission);
        return RAD_ERROR_NO_MEMORY;
    }
    rad_system_surface_means(s, (const rad_rgb *)s->reflectance, reflectance);
    rad_system_surface_means(s, (const rad_rgb *)s->emission, emission);
    for (size_t i = 0; i < s->surface_count; ++i) {
        const char *name = s->surface_name[i] ? s->surface_name[i] : "";
        h = rad_fnv1a(h, name, strlen(name) + 1);
        for (int c = 0; c < 3; ++c) h = hash_f32(hash_f32(h, reflectance[i][c]), emission[i][c]);
    }
    rad_free(s->ctx, reflectance);
    rad_free(s->ctx, emission);
    out->scene = h;

    /* Mesh: the exact elements the solution lives on. */
    h = hash_u64(hash_u64(RAD_FNV1A_START, s->element_count), s->patch_count);
    for (size_t p = 0; p <= s->patch_count; ++p) h = hash_u64(h, s->patch_first[p]);
    for (size_t e = 0; e < s->element_count; ++e) {
        h = hash_u64(h, s->element_surface[e]);
        h = hash_f64(h, s->area[e]);
        for (int c = 0; c < 3; ++c) h = hash_f64(hash_f64(h, s->reflectance[e][c]), s->emission[e][c]);
    }
    const rad_mesh *m = rad_solution_leaves(rad_system_view(s));
    if (m) {
        h = hash_u64(h, m->vertex_count);
        for (size_t v = 0; v < m->vertex_count; ++v)
            h = hash_f64(hash_f64(hash_f64(h, m->vertices[v].x), m->vertices[v].y), m->vertices[v].z);
        for (size_t e = 0; e < m->element_count; ++e)
            for (int k = 0; k < 4; ++k) h = hash_u64(h, m->element_vertices[e][k]);
    }
    out->mesh = h;

    /* Form factors: the method and the first and last rows, bit for bit (providers are
     * deterministic: the same options and seed give the same rows on any thread count). */
    const char *method = s->ff && s->ff->method ? s->ff->method : "";
    h = rad_fnv1a(RAD_FNV1A_START, method, strlen(method) + 1);
    if (s->ff && s->patch_count > 0) {
        float *row = rad_alloc(s->ctx, s->element_count, sizeof *row);
        if (!row) return RAD_ERROR_NO_MEMORY;
        size_t probes[2] = {0, s->patch_count - 1};
        for (int k = 0; k < (s->patch_count > 1 ? 2 : 1); ++k) {
            rad_status status = s->ff->row(s->ff, probes[k], row);
            if (status) {
                rad_free(s->ctx, row);
                return status;
            }
            for (size_t e = 0; e < s->element_count; ++e) {
                uint32_t bits;
                float f = row[e] == 0 ? 0.0f : row[e];
                memcpy(&bits, &f, sizeof bits);
                unsigned char b[4];
                rad_le_put_u32(b, bits);
                h = rad_fnv1a(h, b, 4);
            }
        }
        rad_free(s->ctx, row);
    }
    out->form_factors = h;
    return RAD_OK;
}

rad_status rad_system_save_solution(rad_system *s, const char *path, const rad_solution_info *info) {
    if (!s || !path) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = s->ctx;
    /* The hierarchy's own kind of file (solution_hier.c). */
    if (rad_hier_view_hierarchy(s)) return rad_solution_hier_save(s, path, info);
    /* A file holds one value per element of the system; a view whose leaves are not those
     * elements (a hierarchy's own leaves) cannot be saved this way. */
    const rad_mesh *view_leaves = rad_solution_leaves(rad_system_view(s));
    if (view_leaves && view_leaves->element_count != s->element_count)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: the %s solution has %zu leaves, not one "
                        "per element; solution files cannot hold it", path,
                        rad_system_view(s)->ops->name, view_leaves->element_count);
    rad_solution_fingerprint print;
    rad_status status = rad_solution_fingerprint_compute(s, &print);
    if (status) return status;
    size_t payload, size;
    if (rad_size_mul(s->element_count, RAD_SOLUTION_ELEMENT_SIZE, &payload) ||
        payload > SIZE_MAX - RAD_SOLUTION_HEADER_SIZE - 8)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: the solution is too large", path);
    size = RAD_SOLUTION_HEADER_SIZE + payload + 8;
    unsigned char *bytes = rad_alloc_zero(ctx, size, 1);
    if (!bytes) return RAD_ERROR_NO_MEMORY;
    memcpy(bytes, RAD_SOLUTION_MAGIC, 8);
    rad_le_put_u32(bytes + 8, RAD_SOLUTION_VERSION);
    rad_le_put_u32(bytes + 12, info ? rad_solver_file_code(info->solver) : 0u);
    rad_le_put_u64(bytes + 16, info && info->steps > 0 ? (uint64_t)info->steps : 0u);
    rad_le_put_u64(bytes + 24, s->element_count);
    rad_le_put_u64(bytes + 32, s->patch_count);
    rad_le_put_u64(bytes + 40, s->surface_count);
    rad_le_put_u64(bytes + 48, print.scene);
    rad_le_put_u64(bytes + 56, print.mesh);
    rad_le_put_u64(bytes + 64, print.form_factors);
    for (int c = 0; c < 3; ++c) rad_le_put_f64(bytes + 72 + 8 * c, s->ambient[c]);
    unsigned char *p = bytes + RAD_SOLUTION_HEADER_SIZE;
    const rad_solution_view *view = rad_system_view(s);
    const rad_mesh *leaves = rad_solution_leaves(view);
    for (size_t e = 0; e < s->element_count; ++e, p += RAD_SOLUTION_ELEMENT_SIZE) {
        double radiosity[3], unshot[3], centre = rad_solution_leaf_centre(leaves, e);
        view->ops->radiosity(view, e, centre, centre, radiosity);
        view->ops->unshot(view, e, unshot);
        for (int c = 0; c < 3; ++c) {
            rad_le_put_f64(p + 8 * c, radiosity[c]);
            rad_le_put_f64(p + 24 + 8 * c, unshot[c]);
        }
    }
    rad_le_put_u64(p, rad_fnv1a(RAD_FNV1A_START, bytes, size - 8));

    rad_atomic_file file;
    status = rad_atomic_open(ctx, path, &file);
    if (!status) {
        if (fwrite(bytes, 1, size, file.file) != size) {
            status = rad_fail(ctx, RAD_ERROR_IO, "%s: write failed: %s", path, strerror(errno));
            rad_atomic_abandon(&file);
        } else {
            status = rad_atomic_commit(&file);
        }
    }
    rad_free(ctx, bytes);
    return status;
}

/* Reads the whole of an open file whose first `got` bytes (at most 64 KiB) were read into
 * `first`; *size is its length. */
static rad_status read_all(rad_context *ctx, const char *path, FILE *f, const unsigned char *first,
                           size_t got, unsigned char **out, size_t *size) {
    *out = NULL;
    size_t capacity = 1 << 16, length = got;
    unsigned char *bytes = rad_alloc(ctx, capacity, 1);
    rad_status status = bytes ? RAD_OK : RAD_ERROR_NO_MEMORY;
    if (bytes) memcpy(bytes, first, got);
    while (!status) {
        if (length == capacity) {
            /* A file without end (/dev/zero, a runaway pipe) stops at the memory budget. */
            if ((status = rad_check_budget(ctx, 2.0 * (double)capacity, path))) break;
            unsigned char *grown = capacity > SIZE_MAX / 2 ? NULL : rad_realloc(ctx, bytes, capacity * 2, 1);
            if (!grown) {
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
            bytes = grown;
            capacity *= 2;
        }
        size_t got = fread(bytes + length, 1, capacity - length, f);
        length += got;
        if (got == 0) {
            if (ferror(f)) status = rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
            break;
        }
    }
    if (status) {
        rad_free(ctx, bytes);
        return status;
    }
    *out = bytes;
    *size = length;
    return RAD_OK;
}

/* Checks a file's bytes against the system; nothing is changed. */
static rad_status check_file(rad_system *s, const char *path, const unsigned char *bytes,
                             size_t size) {
    rad_context *ctx = s->ctx;
    if (size < 8 || memcmp(bytes, RAD_SOLUTION_MAGIC, 8) != 0)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a radiosity solution file", path);
    if (size < RAD_SOLUTION_HEADER_SIZE + 8)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%zu bytes)", path, size);
    uint32_t version = rad_le_get_u32(bytes + 8);
    if (version != RAD_SOLUTION_VERSION)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED,
                        "%s: solution file version %u; this build reads versions %u and %u", path,
                        version, RAD_SOLUTION_VERSION, RAD_SOLUTION_HIER_VERSION);
    if (rad_solver_from_file_code(rad_le_get_u32(bytes + 12)) < 0)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: made by an unknown solver (%u)", path,
                        rad_le_get_u32(bytes + 12));
    uint64_t elements = rad_le_get_u64(bytes + 24), patches = rad_le_get_u64(bytes + 32);
    if (elements > (SIZE_MAX - RAD_SOLUTION_HEADER_SIZE - 8) / RAD_SOLUTION_ELEMENT_SIZE)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (element count %llu)",
                        path, (unsigned long long)elements);
    size_t expected = RAD_SOLUTION_HEADER_SIZE + (size_t)elements * RAD_SOLUTION_ELEMENT_SIZE + 8;
    if (size < expected)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: truncated solution file (%zu of %zu bytes)",
                        path, size, expected);
    if (size > expected || rad_le_get_u64(bytes + expected - 8) != rad_fnv1a(RAD_FNV1A_START, bytes, expected - 8))
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (checksum mismatch)", path);

    rad_solution_fingerprint print;
    rad_status status = rad_solution_fingerprint_compute(s, &print);
    if (status) return status;
    if (rad_le_get_u64(bytes + 48) != print.scene || rad_le_get_u64(bytes + 40) != s->surface_count)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different scene (surfaces or materials differ)", path);
    if (elements != s->element_count || patches != s->patch_count || rad_le_get_u64(bytes + 56) != print.mesh)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved for a different mesh or geometry (%llu elements in %llu "
                        "patches; this one has %zu in %zu): use the same scene and meshing options",
                        path, (unsigned long long)elements, (unsigned long long)patches,
                        s->element_count, s->patch_count);
    if (rad_le_get_u64(bytes + 64) != print.form_factors)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "%s: saved with different form factors (method, samples or seed): use the "
                        "same form-factor options", path);
    for (size_t i = 72; i < expected - 8; i += 8)
        if (!isfinite(rad_le_get_f64(bytes + i)))
            return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (a value is not finite)",
                            path);
    /* Radiosity is never negative: an iteration may leave rounding below zero (a millionth of
     * the largest), no more. Unshot radiosity may be negative (overshooting). */
    double largest = 0;
    for (size_t i = 72; i < expected - 8; i += 8) largest = fmax(largest, fabs(rad_le_get_f64(bytes + i)));
    for (size_t e = 0; e < s->element_count; ++e)
        for (int c = 0; c < 3; ++c) {
            double radiosity = rad_le_get_f64(bytes + RAD_SOLUTION_HEADER_SIZE + 48 * e + 8 * c);
            if (radiosity < -1e-6 * largest)
                return rad_fail(ctx, RAD_ERROR_PARSE, "%s: corrupted solution file (element %zu "
                                "has a negative radiosity, %g)", path, e, radiosity);
        }
    return RAD_OK;
}

rad_status rad_solution_file_info(rad_context *ctx, const char *path, rad_solution_info *info) {
    if (!path || !info) return RAD_ERROR_INVALID_ARGUMENT;
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(ctx, RAD_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    unsigned char head[24];
    size_t got = fread(head, 1, sizeof head, file);
    fclose(file);
    if (got < sizeof head || memcmp(head, RAD_SOLUTION_MAGIC, 8) != 0)
        return rad_fail(ctx, RAD_ERROR_PARSE, "%s: not a radiosity solution file", path);
    uint32_t version = rad_le_get_u32(head + 8);
    int solver = rad_solver_from_file_code(rad_le_get_u32(head + 12));
    if ((version != RAD_SOLUTION_VERSION && version != RAD_SOLUTION_HIER_VERSION) || solver < 0)
        return rad_fail(ctx, RAD_ERROR_UNSUPPORTED, "%s: solution file version %u, solver %u: "
                        "not one this build reads", path, version, rad_le_get_u32(head + 12));
    info->solver = (rad_solver_kind)solver;
    info->steps = (long)rad_le_get_u64(head + 16);
    return RAD_OK;
}

rad_status rad_system_load_solution(rad_system *s, const char *path, rad_solution_info *info) {
    if (!s || !path) return RAD_ERROR_INVALID_ARGUMENT;
    FILE *file = fopen(path, "rb");
    if (!file) return rad_fail(s->ctx, RAD_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    /* A hierarchy's file (version 2) is read as a stream, never whole (solution_hier.c). */
    unsigned char head[12];
    size_t got = fread(head, 1, sizeof head, file);
    if (got == sizeof head && memcmp(head, RAD_SOLUTION_MAGIC, 8) == 0 &&
        rad_le_get_u32(head + 8) == RAD_SOLUTION_HIER_VERSION) {
        rad_status status = rad_solution_hier_load(s, path, file, info);
        fclose(file);
        return status;
    }
    unsigned char *bytes = NULL;
    size_t size = 0;
    rad_status status = read_all(s->ctx, path, file, head, got, &bytes, &size);
    fclose(file);
    if (status) return status;
    status = check_file(s, path, bytes, size);
    if (!status && !rad_system_view(s)->ops->store)
        status = rad_fail(s->ctx, RAD_ERROR_UNSUPPORTED, "%s: the %s solution cannot be restored "
                          "from a solution file", path, rad_system_view(s)->ops->name);
    if (!status) {
        for (int c = 0; c < 3; ++c) s->ambient[c] = rad_le_get_f64(bytes + 72 + 8 * c);
        const unsigned char *p = bytes + RAD_SOLUTION_HEADER_SIZE;
        rad_solution_view *view = rad_system_view_mutable(s);
        for (size_t e = 0; e < s->element_count; ++e, p += RAD_SOLUTION_ELEMENT_SIZE) {
            double radiosity[3], unshot[3];
            for (int c = 0; c < 3; ++c) {
                radiosity[c] = rad_le_get_f64(p + 8 * c);
                unshot[c] = rad_le_get_f64(p + 24 + 8 * c);
            }
            view->ops->store(view, e, radiosity, unshot);
        }
        if (info) {
            info->solver = (rad_solver_kind)rad_solver_from_file_code(rad_le_get_u32(bytes + 12));
            info->steps = (long)rad_le_get_u64(bytes + 16);
        }
    }
    rad_free(s->ctx, bytes);
    return status;
}
