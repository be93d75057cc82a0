/* roots.c - the contact-cut quads and triangles a hierarchy starts from (see roots.h). */
#include "mesh/roots.h"

#include "mesh/contact.h"
#include "scene/scene.h"

#include <math.h>
#include <string.h>

/* Corners where a piece turns by less than this (the sine of the angle) are dropped. */
#define STRAIGHT 1e-7

static double corners_area(const rad_vec3 *c, int count) {
    if (count == 3) return 0.5 * v3_length(v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0])));
    return 0.5 * v3_length(v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1])));
}

/* Keeps the corners of p[0 .. n-1] where the outline turns; returns how many are left. */
static size_t drop_straight(rad_vec3 *p, size_t n) {
    size_t kept = n;
    for (int changed = 1; changed && kept > 3;) {
        changed = 0;
        for (size_t i = 0; i < kept && kept > 3; ++i) {
            rad_vec3 a = v3_sub(p[i], p[(i + kept - 1) % kept]);
            rad_vec3 b = v3_sub(p[(i + 1) % kept], p[i]);
            double turn = v3_length(v3_cross(a, b)), scale = v3_length(a) * v3_length(b);
            if (turn <= STRAIGHT * scale) {
                memmove(p + i, p + i + 1, (kept - i - 1) * sizeof *p);
                --kept;
                changed = 1;
            }
        }
    }
    return kept;
}

static rad_status add_root(rad_context *ctx, rad_roots *r, size_t *capacity, uint32_t polygon,
                           const rad_vec3 *c, int count) {
    double area = corners_area(c, count);
    if (!(area > 0) || !isfinite(area)) return RAD_OK;
    if (r->count == *capacity) {
        size_t next = *capacity ? 2 * *capacity : 64;
        rad_root *grown = rad_realloc(ctx, r->roots, next, sizeof *grown);
        if (!grown) return RAD_ERROR_NO_MEMORY;
        r->roots = grown;
        *capacity = next;
    }
    rad_root *root = &r->roots[r->count++];
    memset(root, 0, sizeof *root);
    memcpy(root->corner, c, (size_t)count * sizeof *c);
    root->count = (uint32_t)count;
    root->area = area;
    root->polygon = polygon;
    return RAD_OK;
}

rad_status rad_roots_create(rad_context *ctx, const rad_scene *scene, int quiet, rad_roots **out) {
    *out = NULL;
    rad_contact_cut *cut = NULL;
    rad_contact_options options = {0};
    /* Touching contacts, and what a polygon just in front seals (the ceiling behind the lamp
     * panel); not the near-parallel cut at large: a sky's part behind a roof is seen through
     * the roof's opening (docs/hierarchical.md, "The roots cut where a polygon seals another"). */
    options.no_near = 1;
    options.sealed = 1;
    options.quiet = quiet;
    options.sparing = 1;
    rad_status status = rad_contact_cut_create_with(ctx, scene, &options, &cut);
    if (status) return status;
    rad_roots *r = rad_alloc_zero(ctx, 1, sizeof *r);
    rad_vec3 *p = NULL;
    size_t p_capacity = 0, capacity = 0;
    if (!r) status = RAD_ERROR_NO_MEMORY;
    for (size_t i = 0; i < (r ? cut->piece_count : 0) && !status; ++i) {
        const rad_contact_piece *piece = &cut->pieces[i];
        if (piece->count < 3) continue;
        if (piece->count > p_capacity) {
            rad_free(ctx, p);
            p_capacity = piece->count;
            if (!(p = rad_alloc(ctx, p_capacity, sizeof *p))) {
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
        }
        memcpy(p, cut->points + piece->first, piece->count * sizeof *p);
        size_t n = drop_straight(p, piece->count);
        if (n <= 4) {
            status = add_root(ctx, r, &capacity, piece->polygon, p, (int)n);
            continue;
        }
        /* Larger convex pieces: a fan of quads from the first corner, a triangle to close. */
        size_t k = 1;
        for (; k + 2 < n && !status; k += 2) {
            rad_vec3 q[4] = {p[0], p[k], p[k + 1], p[k + 2]};
            status = add_root(ctx, r, &capacity, piece->polygon, q, 4);
        }
        if (k + 1 < n && !status) {
            rad_vec3 t[3] = {p[0], p[k], p[k + 1]};
            status = add_root(ctx, r, &capacity, piece->polygon, t, 3);
        }
    }
    if (r) {
        r->hidden_pieces = cut->hidden_pieces + cut->covered_pieces;
        r->hidden_area = cut->hidden_area;
    }
    rad_free(ctx, p);
    rad_contact_cut_destroy(ctx, cut);
    if (status) {
        rad_roots_destroy(ctx, r);
        return status;
    }
    *out = r;
    return RAD_OK;
}

void rad_roots_destroy(rad_context *ctx, rad_roots *roots) {
    if (!roots) return;
    rad_free(ctx, roots->roots);
    rad_free(ctx, roots);
}
