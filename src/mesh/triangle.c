/* triangle.c - a triangle cut to given side counts (see triangle.h, docs/meshing.md).
 *
 * Each side of a triangle keeps the count its own length (or a quad next to it) asks for, so
 * the three counts a, b, c of one triangle may differ. The interior is cut to match them:
 *
 * - three quads: when a + b + c is even and each count is less than the sum of the other two,
 *   the triangle splits into three quads meeting at an interior point G, each cut as a grid
 *   ("midpoint subdivision", Li, McKeag and Armstrong 1995; CUBIT's TriPrimitive scheme). The
 *   grids' opposite sides must agree, which fixes the split of each side: A = (a + b - c) / 2,
 *   B = (b + c - a) / 2, C = (c + a - b) / 2. G is where the three lines from each corner
 *   through the opposite split point meet (they do, by Ceva's theorem), barycentric (C, A, B):
 *   then every piece of the inner lines is at most the longest side piece, so no element edge
 *   exceeds the element size.
 * - strips: when two sides have the same count n, rows parallel to the third side at 1/n, 2/n,
 *   ... of the way from the corner between them; each row is cut into as many pieces as its
 *   length asks for and neighbouring rows are zipped together with quads and, where a row has
 *   more pieces than the next, triangles. This serves needles (1, n, n) and odd sums.
 * - peeling: otherwise a line from a corner to a cut point of the opposite side splits off a
 *   triangle with two equal counts (cut by strips or three quads) and leaves a triangle whose
 *   counts have an even sum (the line's count is chosen so), cut the same way in turn.
 * - a fan from the centroid, only if peeling goes too deep (never seen; it keeps the mesh
 *   conforming whatever the counts).
 *
 * Patches: the blocks of k x k elements of each quad grid, bands of at most k strips of at most
 * k pieces, or runs of k elements along a longer strip; every one is a convex region (a block
 * of a quad grid, or the part of a triangle between two straight lines). A triangle whose sides
 * all have at most k pieces is one patch. */
#include "mesh/triangle.h"

#include <math.h>

#define PEEL_DEPTH 24
#define OBTUSE (RAD_PI * 2 / 3) /* 120 degrees: measured, docs/meshing.md */

size_t tri_scratch_size(uint32_t largest) {
    size_t line = (size_t)largest + 3;
    return line * line + (PEEL_DEPTH + 8) * line;
}

/* ------------------------------------------------------------------------------------------- */
/* Sides, vertices, elements, patches.                                                          */

static uint32_t side_id(const tri_side *s, uint32_t i) {
    if (!s->ids) return 0;
    return s->ids[s->reverse ? s->count - i : i];
}

/* Pieces from .. from + count of a side, in the same direction. */
static tri_side side_part(const tri_side *s, uint32_t from, uint32_t count) {
    tri_side part = {NULL, count, s->reverse};
    if (s->ids) part.ids = s->reverse ? s->ids + (s->count - from - count) : s->ids + from;
    return part;
}

static tri_side side_reversed(tri_side s) {
    s.reverse = !s.reverse;
    return s;
}

static uint32_t *take(tri_out *out, size_t count) {
    if (!out->mesh || out->scratch_used + count > out->scratch_size) return NULL;
    uint32_t *ids = out->scratch + out->scratch_used;
    out->scratch_used += count;
    return ids;
}

static uint32_t new_vertex(tri_out *out, rad_vec3 p) {
    out->vertices++;
    rad_mesh *mesh = out->mesh;
    if (!mesh) return 0;
    mesh->vertices[mesh->vertex_count] = p;
    mesh->vertex_surface[mesh->vertex_count] = out->surface;
    return (uint32_t)mesh->vertex_count++;
}

static void new_element(tri_out *out, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    out->elements++;
    if (out->mesh) rad_mesh_put_element(out->mesh, out->polygon, out->surface, a, b, c, d);
}

/* Closes the patch of the elements made since `first` (an element count), if there are any. */
static void close_patch(tri_out *out, size_t first) {
    if (out->elements == first) return;
    out->patches++;
    rad_mesh *mesh = out->mesh;
    if (mesh) mesh->patch_first[++mesh->patch_count] = mesh->element_count;
}

/* A line of count pieces from vertex `from` at a to vertex `to` at b, new vertices inside. */
static tri_side new_line(tri_out *out, rad_vec3 a, rad_vec3 b, uint32_t from, uint32_t to,
                         uint32_t count) {
    uint32_t *ids = take(out, (size_t)count + 1);
    for (uint32_t t = 1; t < count; ++t) {
        uint32_t v = new_vertex(out, v3_lerp(a, b, (double)t / count));
        if (ids) ids[t] = v;
    }
    if (ids) ids[0] = from, ids[count] = to;
    return (tri_side){ids, count, 0};
}

static uint32_t pieces(double length, double element_size) {
    return (uint32_t)fmax(1.0, fmin(ceil(length / element_size - 1e-9), 1e6));
}

static double smallest_angle(rad_vec3 a, rad_vec3 b, rad_vec3 c) {
    rad_vec3 p[3] = {a, b, c};
    double smallest = RAD_PI;
    for (int k = 0; k < 3; ++k) {
        rad_vec3 u = v3_sub(p[(k + 1) % 3], p[k]), w = v3_sub(p[(k + 2) % 3], p[k]);
        smallest = fmin(smallest, atan2(v3_length(v3_cross(u, w)), v3_dot(u, w)));
    }
    return smallest;
}

/* ------------------------------------------------------------------------------------------- */
/* Three quads.                                                                                 */

/* A convex quad q[0..3] whose sides s[0] (q0 -> q1) and s[2] (q2 -> q3) have nu pieces and
 * s[1], s[3] nv: a bilinear grid in k x k blocks. */
static void cut_grid(tri_out *out, const rad_vec3 q[4], const tri_side s[4]) {
    uint32_t nu = s[0].count, nv = s[1].count, k = out->k;
    size_t mark = out->scratch_used;
    uint32_t *grid = take(out, (size_t)(nu + 1) * (nv + 1));
#define ID(i, j) (grid ? grid[(size_t)(j) * (nu + 1) + (i)] : 0)
    for (uint32_t j = 0; j <= nv; ++j)
        for (uint32_t i = 0; i <= nu; ++i) {
            uint32_t v;
            if (j == 0) v = side_id(&s[0], i);
            else if (i == nu) v = side_id(&s[1], j);
            else if (j == nv) v = side_id(&s[2], nu - i);
            else if (i == 0) v = side_id(&s[3], nv - j);
            else {
                double u = (double)i / nu, t = (double)j / nv;
                v = new_vertex(out, v3_add(v3_add(v3_scale(q[0], (1 - u) * (1 - t)), v3_scale(q[1], u * (1 - t))),
                                           v3_add(v3_scale(q[2], u * t), v3_scale(q[3], (1 - u) * t))));
            }
            if (grid) grid[(size_t)j * (nu + 1) + i] = v;
        }
    /* The grid, for ray queries (mesh.h): its elements follow in mesh.c's cut_quad order. */
    out->grids++;
    if (out->mesh && grid && out->grid_room > 0) {
        out->grid_room--;
        out->mesh->grids[out->mesh->grid_count++] =
            (rad_mesh_grid){{ID(0, 0), ID(nu, 0), ID(nu, nv), ID(0, nv)},
                            (uint32_t)out->mesh->element_count, nu, nv, k};
    }
    for (uint32_t pj = 0; pj < nv; pj += k)
        for (uint32_t pi = 0; pi < nu; pi += k) {
            size_t first = out->elements;
            for (uint32_t j = pj; j < pj + k && j < nv; ++j)
                for (uint32_t i = pi; i < pi + k && i < nu; ++i)
                    new_element(out, ID(i, j), ID(i + 1, j), ID(i + 1, j + 1), ID(i, j + 1));
            close_patch(out, first);
        }
#undef ID
    out->scratch_used = mark;
}

static void cut_three_quads(tri_out *out, const rad_vec3 p[3], const tri_side s[3]) {
    uint32_t a = s[0].count, b = s[1].count, c = s[2].count;
    uint32_t A = (a + b - c) / 2, B = (b + c - a) / 2, C = (c + a - b) / 2;
    size_t mark = out->scratch_used;
    /* Split points: A pieces from p0 on side 0, B from p1 on side 1, C from p2 on side 2. */
    rad_vec3 s01 = v3_lerp(p[0], p[1], (double)A / a), s12 = v3_lerp(p[1], p[2], (double)B / b),
             s20 = v3_lerp(p[2], p[0], (double)C / c);
    rad_vec3 g = v3_scale(v3_add(v3_add(v3_scale(p[0], C), v3_scale(p[1], A)), v3_scale(p[2], B)),
                          1.0 / (A + B + C));
    uint32_t gid = new_vertex(out, g);
    /* Inner lines to G; their counts are those of the opposite sides of the quads they bound. */
    tri_side e01 = new_line(out, s01, g, side_id(&s[0], A), gid, B);
    tri_side e12 = new_line(out, s12, g, side_id(&s[1], B), gid, C);
    tri_side e20 = new_line(out, s20, g, side_id(&s[2], C), gid, A);
    const rad_vec3 q0[4] = {p[0], s01, g, s20}, q1[4] = {p[1], s12, g, s01}, q2[4] = {p[2], s20, g, s12};
    const tri_side t0[4] = {side_part(&s[0], 0, A), e01, side_reversed(e20), side_part(&s[2], C, B)};
    const tri_side t1[4] = {side_part(&s[1], 0, B), e12, side_reversed(e01), side_part(&s[0], A, C)};
    const tri_side t2[4] = {side_part(&s[2], 0, C), e20, side_reversed(e12), side_part(&s[1], B, A)};
    cut_grid(out, q0, t0);
    cut_grid(out, q1, t1);
    cut_grid(out, q2, t2);
    out->scratch_used = mark;
}

/* ------------------------------------------------------------------------------------------- */
/* Strips.                                                                                      */

/* Rows parallel to the side opposite corner q, whose two sides have the same count n. */
static void cut_strips(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int q) {
    const tri_side *left = &s[q], *base = &s[(q + 1) % 3], *right = &s[(q + 2) % 3];
    uint32_t n = left->count, m = base->count, k = out->k;
    rad_vec3 apex = p[q], l = p[(q + 1) % 3], r = p[(q + 2) % 3];
    size_t mark = out->scratch_used;
    uint32_t *top = take(out, (size_t)m + 2), *bottom = take(out, (size_t)m + 2);
    uint32_t top_count = 0;
    if (top) top[0] = side_id(left, 0);
    size_t band_first = out->elements;
    uint32_t band_rows = 0;
    for (uint32_t row = 1; row <= n; ++row) {
        /* Row `row`: from the left side's cut `row` to the right side's, cut to its length. */
        uint32_t count = row == n ? m : (uint32_t)fmin(m, fmax(1, ceil((double)row * m / n - 1e-9)));
        rad_vec3 from = v3_lerp(apex, l, (double)row / n), to = v3_lerp(apex, r, (double)row / n);
        for (uint32_t i = 0; i <= count; ++i) {
            uint32_t v;
            if (i == 0) v = side_id(left, row);
            else if (i == count) v = side_id(right, n - row);
            else if (row == n) v = side_id(base, i);
            else v = new_vertex(out, v3_lerp(from, to, (double)i / count));
            if (bottom) bottom[i] = v;
        }
        /* Patches: bands of up to k rows of up to k pieces; a longer row alone, in runs of k. */
        int long_row = count > k;
        if (band_rows == k || (long_row && band_rows > 0)) {
            close_patch(out, band_first);
            band_first = out->elements;
            band_rows = 0;
        }
        /* Zip the row to the one above: advance along both (a quad) or along one (a triangle),
         * whichever keeps the new cross edge closest to the rows' common direction. */
        uint32_t i = 0, j = 0;
        size_t run_first = out->elements;
#define B(x) (bottom ? bottom[x] : 0)
#define T(x) (top ? top[x] : 0)
        while (i < count || j < top_count) {
            int move; /* 0 quad, 1 along the bottom, 2 along the top */
            if (j == top_count) move = 1;
            else if (i == count) move = 2;
            else {
                double bi = (double)i / count, bn = (double)(i + 1) / count;
                double tj = (double)j / top_count, tn = (double)(j + 1) / top_count;
                double dq = fabs(bn - tn), db = fabs(bn - tj), dt = fabs(bi - tn);
                move = dq <= db && dq <= dt ? 0 : db <= dt ? 1 : 2;
            }
            if (move == 0) new_element(out, B(i), B(i + 1), T(j + 1), T(j)), ++i, ++j;
            else if (move == 1) new_element(out, B(i), B(i + 1), T(j), RAD_NO_VERTEX), ++i;
            else new_element(out, B(i), T(j + 1), T(j), RAD_NO_VERTEX), ++j;
            if (long_row && out->elements - run_first == k) {
                close_patch(out, run_first);
                run_first = out->elements;
            }
        }
#undef B
#undef T
        if (long_row) {
            close_patch(out, run_first);
            band_first = out->elements;
        } else {
            band_rows++;
        }
        uint32_t *swap = top;
        top = bottom;
        bottom = swap;
        top_count = count;
    }
    close_patch(out, band_first);
    out->scratch_used = mark;
}

/* ------------------------------------------------------------------------------------------- */
/* Peeling and the fan.                                                                         */

static void cut_at(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int depth);
static void cut_split(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int si, uint32_t at,
                      uint32_t lines, int depth);

/* Splits off, at one end of side `si`, the triangle whose two sides at that corner have the
 * same count, by a line from the opposite corner; the line's count makes the rest's sum even.
 * Of the (up to six) ways, the one leaving a triangle for three quads, then the best shaped. */
static int cut_peeled(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int depth) {
    uint32_t total = s[0].count + s[1].count + s[2].count;
    int best_side = -1, best_end = 0;
    uint32_t best_lines = 0;
    double best_score = -1;
    for (int si = 0; si < 3; ++si)
        for (int end = 0; end < 2; ++end) {
            uint32_t n = s[si].count, x = end == 0 ? s[(si + 2) % 3].count : s[(si + 1) % 3].count;
            if (x >= n) continue;
            uint32_t at = end == 0 ? x : n - x;
            rad_vec3 cut = v3_lerp(p[si], p[(si + 1) % 3], (double)at / n), corner = p[(si + 2) % 3];
            uint32_t lines = pieces(v3_length(v3_sub(corner, cut)), out->element_size);
            if ((lines + total) % 2) lines++;
            /* The rest: (n - x, the far side, lines), even by construction. */
            uint32_t r0 = n - x, r1 = end == 0 ? s[(si + 1) % 3].count : s[(si + 2) % 3].count;
            int quads = r0 < r1 + lines && r1 < r0 + lines && lines < r0 + r1;
            double shape = end == 0 ? fmin(smallest_angle(p[si], cut, corner),
                                           smallest_angle(cut, p[(si + 1) % 3], corner))
                                    : fmin(smallest_angle(cut, p[(si + 1) % 3], corner),
                                           smallest_angle(p[si], cut, corner));
            double score = shape + (quads ? 10 : 0);
            if (score > best_score) best_score = score, best_side = si, best_end = end, best_lines = lines;
        }
    if (best_side < 0) return 0;
    uint32_t n = s[best_side].count;
    uint32_t x = best_end == 0 ? s[(best_side + 2) % 3].count : s[(best_side + 1) % 3].count;
    cut_split(out, p, s, best_side, best_end == 0 ? x : n - x, best_lines, depth);
    return 1;
}

/* An obtuse triangle's three quads would meet at a point near its long side, with corners
 * close to 180 degrees: first split it by a line from the wide corner to the cut point nearest
 * the foot of its altitude, into two triangles with no wide corner. The line's count keeps
 * both sums even (their sum is even, so one fixes the other). */
static int cut_obtuse(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int depth) {
    int wide = -1;
    double widest = 0;
    for (int q = 0; q < 3; ++q) {
        rad_vec3 u = v3_sub(p[(q + 1) % 3], p[q]), w = v3_sub(p[(q + 2) % 3], p[q]);
        double angle = atan2(v3_length(v3_cross(u, w)), v3_dot(u, w));
        if (angle > widest) widest = angle, wide = q;
    }
    int si = (wide + 1) % 3; /* the long side, opposite the wide corner */
    uint32_t n = s[si].count;
    if (widest < OBTUSE || n < 2) return 0;
    rad_vec3 a = p[si], b = p[(si + 1) % 3], d = v3_sub(b, a);
    double foot = v3_dot(v3_sub(p[wide], a), d) / v3_dot(d, d);
    uint32_t at = (uint32_t)fmin(n - 1, fmax(1, floor(foot * n + 0.5)));
    rad_vec3 cut = v3_lerp(a, b, (double)at / n);
    uint32_t lines = pieces(v3_length(v3_sub(p[wide], cut)), out->element_size);
    if ((at + s[(si + 2) % 3].count + lines) % 2) lines++;
    cut_split(out, p, s, si, at, lines, depth);
    return 1;
}

/* Splits by a line of `lines` pieces from cut `at` of side si to the opposite corner. */
static void cut_split(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int si, uint32_t at,
                      uint32_t lines, int depth) {
    int sj = (si + 1) % 3, sk = (si + 2) % 3;
    uint32_t n = s[si].count;
    rad_vec3 cut = v3_lerp(p[si], p[sj], (double)at / n);
    size_t mark = out->scratch_used;
    tri_side line = new_line(out, cut, p[sk], side_id(&s[si], at), side_id(&s[sk], 0), lines);
    /* Two counter-clockwise triangles: (p_i, cut, p_k) and (cut, p_j, p_k). */
    const rad_vec3 first[3] = {p[si], cut, p[sk]}, second[3] = {cut, p[sj], p[sk]};
    const tri_side first_sides[3] = {side_part(&s[si], 0, at), line, s[sk]};
    const tri_side second_sides[3] = {side_part(&s[si], at, n - at), s[sj], side_reversed(line)};
    cut_at(out, first, first_sides, depth + 1);
    cut_at(out, second, second_sides, depth + 1);
    out->scratch_used = mark;
}

/* Every boundary piece joined to the centroid; patches are runs along one side. */
static void cut_fan(tri_out *out, const rad_vec3 p[3], const tri_side s[3]) {
    uint32_t centre = new_vertex(out, v3_scale(v3_add(v3_add(p[0], p[1]), p[2]), 1.0 / 3));
    for (int si = 0; si < 3; ++si) {
        size_t first = out->elements;
        for (uint32_t i = 0; i < s[si].count; ++i) {
            new_element(out, side_id(&s[si], i), side_id(&s[si], i + 1), centre, RAD_NO_VERTEX);
            if (out->elements - first == (size_t)out->k * out->k) {
                close_patch(out, first);
                first = out->elements;
            }
        }
        close_patch(out, first);
    }
}

static void cut_at(tri_out *out, const rad_vec3 p[3], const tri_side s[3], int depth) {
    uint32_t a = s[0].count, b = s[1].count, c = s[2].count;
    if (a == 1 && b == 1 && c == 1) {
        size_t first = out->elements;
        new_element(out, side_id(&s[0], 0), side_id(&s[1], 0), side_id(&s[2], 0), RAD_NO_VERTEX);
        close_patch(out, first);
        return;
    }
    if ((a + b + c) % 2 == 0 && a < b + c && b < c + a && c < a + b) {
        if (depth < PEEL_DEPTH && cut_obtuse(out, p, s, depth)) return;
        cut_three_quads(out, p, s);
        return;
    }
    /* Two equal counts: strips from the corner between them (of three, the widest corner). */
    int apex = -1;
    double widest = -1;
    for (int q = 0; q < 3; ++q) {
        if (s[q].count != s[(q + 2) % 3].count) continue;
        rad_vec3 u = v3_sub(p[(q + 1) % 3], p[q]), w = v3_sub(p[(q + 2) % 3], p[q]);
        double angle = atan2(v3_length(v3_cross(u, w)), v3_dot(u, w));
        if (angle > widest) widest = angle, apex = q;
    }
    if (apex >= 0) {
        cut_strips(out, p, s, apex);
        return;
    }
    if (depth < PEEL_DEPTH && cut_peeled(out, p, s, depth)) return;
    cut_fan(out, p, s);
}

void tri_cut(tri_out *out, const rad_vec3 p[3], const tri_side side[3]) {
    size_t first_patch = out->patches;
    size_t mesh_element = out->mesh ? out->mesh->element_count : 0;
    size_t mesh_patch = out->mesh ? out->mesh->patch_count : 0;
    cut_at(out, p, side, 0);
    /* A triangle no larger than a block of k x k square elements (in area, and in extent: its
     * longest side at most the block's diagonal) is one patch; it is convex. */
    double size = out->k * out->element_size, longest = 0;
    for (int s = 0; s < 3; ++s) longest = fmax(longest, v3_length(v3_sub(p[(s + 1) % 3], p[s])));
    double area = 0.5 * v3_length(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])));
    if (out->patches - first_patch > 1 && area <= size * size && longest <= sqrt(2.0) * size) {
        out->patches = first_patch + 1;
        rad_mesh *mesh = out->mesh;
        if (mesh) {
            mesh->patch_count = mesh_patch + 1;
            mesh->patch_first[mesh->patch_count] = mesh->element_count;
            for (size_t e = mesh_element; e < mesh->element_count; ++e) mesh->element_patch[e] = (uint32_t)mesh_patch;
        }
    }
}
