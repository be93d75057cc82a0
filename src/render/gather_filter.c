/* gather_filter.c - irradiance filtering of the final gather: the gathered (indirect) light of
 * each pixel replaced by a weighted mean over its neighbours on the same polygon.
 *
 * The final gather's noise is in the light its gather rays read from the solution (the emitter
 * samples are few and stratified; docs/rendering.md, "Choosing the defaults"). That light, the
 * irradiance of the indirect field, varies slowly over a surface except where other surfaces
 * are near (a block's base, a room's corner): Ward's irradiance cache bounds its relative change
 * over a step dx by dx / R, R the harmonic mean distance of what the hemisphere sees (Ward,
 * Rubinstein & Clear 1988). So every pixel's own estimate, from its S n gather rays, is
 * replaced by the mean of its neighbours' estimates within a world-space radius A R (Kontkanen,
 * Raesaenen & Keller 2004, "Irradiance filtering for Monte Carlo ray tracing"): many pixels'
 * rays in open areas, few or none beside a contact, where R is small.
 *
 *   - Which pixels: those whose camera samples all met one untextured diffuse input polygon and
 *     were gathered there (render.c, rad_gather_pixel_make); edge pixels (split by coverage),
 *     pixels seen through mirrors or glass, textured ones, and those on an emitter's surface
 *     stay as they are, and are nobody's neighbours. Neighbours must lie on the same polygon:
 *     a wall and the floor, or a block's faces, never mix.
 *   - The weight of neighbour q for pixel p: (1 - (d / h)^2)^2, d = |x_q - x_p|, h = A min(R_p,
 *     R_q) but at least FLOOR_REACH R_p kept within FEWEST_PIXELS..MIN_PIXELS pixels at p's
 *     depth, zero beyond h; the window is cut at MAX_PIXELS pixels each way. Near a concave corner R shrinks to the distance from it and
 *     Ward's bound keeps every pixel alone, though the light there varies mostly with the
 *     radiosity of the other wall, which is smooth: the few pixels' floor halves the noise
 *     along the room's corner lines. Edge pixels, which are not filtered, gather EDGE_GATHER
 *     times the rays instead (render.c).
 *   - Only the gathered part moves: the pixel's value changes by rho (I' - I), I its own mean
 *     gathered radiance, I' the weighted mean; direct light (emitter samples and the emitted
 *     light the gather rays met, weighted) keeps its own sharp shadows.
 *   - Local quadratic regression (the value at the pixel of a quadric in screen offsets fitted
 *     by weighted least squares, not the plain weighted mean): where the window is cut by the
 *     polygon's edge or the image's, a plain mean would be pulled towards the inside, and where
 *     the light is curved (rising towards a near lit face) a plane's value is off by the
 *     curvature times the window's spread; the quadric's is neither, to second order, so its
 *     window may be wider. Where the quadric is ill-conditioned, the plane (until cornell50 the
 *     only fit); where that is too (a line of pixels), the plain mean.
 * The result depends on the pixels' records only, not on the order of the work: the same bits
 * for any thread count. */
#include "render/render.h"

#include <float.h>
#include <omp.h>

#define RADIUS 0.1     /* A: the filter's radius in harmonic mean distances */
/* ... but at least FLOOR_REACH R, kept between FEWEST_PIXELS and MIN_PIXELS pixels (at the
 * pixel's depth); the window's half-size MAX_PIXELS. With the plane fit (until cornell50) the
 * floor was a plain 4 pixels and the window 12: a wider one bent the plane over curved light
 * (the Cornell box's short block's top +1 % in 16x16 blocks), a larger floor too. With the
 * quadric a floor of 12 pixels halves the noise it adds, but at 64 x 64 pixels that is a fifth of
 * the box and blurred the contact shadow in front of the short block (tests/test_render.c: +11 %
 * against the path tracer, +1 % with the floor held to half of R). */
#define FLOOR_REACH 0.5
#define FEWEST_PIXELS 4.0
#define MIN_PIXELS 12.0
#define MAX_PIXELS 24

void rad_gather_pixel_make(const rad_gather_tally *tally, int samples, uint32_t polygon, int split,
                           rad_gather_pixel *out) {
    *out = (rad_gather_pixel){.polygon = RAD_RENDER_NO_POLYGON}; /* every field defined: the
                                                                     filter packs every record */
    if (split || polygon == RAD_RENDER_NO_POLYGON || tally->gathers != samples || samples <= 0 ||
        tally->rays == 0 || !(tally->inverse_distance > 0))
        return;
    out->polygon = polygon;
    for (int c = 0; c < 3; ++c) {
        out->position[c] = (float)(tally->position[c] / samples);
        out->reflected[c] = (float)(tally->reflected[c] / samples);
        out->rho[c] = tally->rho[c];
    }
    out->distance = (float)(tally->rays / tally->inverse_distance);
}

/* What the filter reads of the neighbours, one array per field, so that a row's neighbours are
 * taken FILTER_LANES at a time in vector registers. inverse_reach2 is 1 / (A R)^2. Each array
 * has FILTER_LANES entries of padding after the last pixel (a row's last lanes may read past
 * its end; they weigh 0). */
#define FILTER_LANES 8
typedef struct filter_neighbours {
    float *x, *y, *z, *inverse_reach2, *reflected[3];
    uint32_t *polygon;
} filter_neighbours;

/* The quadric a + b dx + c dy + d dx^2 + e dx dy + f dy^2 fitted by weighted least squares from
 * the moments of filter_pixel; its value a at the pixel into out. 0 when the normal equations,
 * scaled to a unit diagonal, have a pivot under QUADRIC_PIVOT (the window a line, or too narrow
 * along one axis for a curvature). Gaussian elimination with partial pivoting. */
#define QUADRIC_PIVOT 1e-4
static int fit_quadric(double m[5][5], double rhs[3][3][3], double out[3]) {
    static const int power[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
    double n[6][6], v[6][3], scale[6];
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) n[i][j] = m[power[i][0] + power[j][0]][power[i][1] + power[j][1]];
        for (int c = 0; c < 3; ++c) v[i][c] = rhs[power[i][0]][power[i][1]][c];
        if (!(n[i][i] > 0)) return 0;
        scale[i] = 1 / sqrt(n[i][i]);
    }
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) n[i][j] *= scale[i] * scale[j];
        for (int c = 0; c < 3; ++c) v[i][c] *= scale[i];
    }
    for (int i = 0; i < 6; ++i) {
        int pivot = i;
        for (int r = i + 1; r < 6; ++r)
            if (fabs(n[r][i]) > fabs(n[pivot][i])) pivot = r;
        if (!(fabs(n[pivot][i]) >= QUADRIC_PIVOT)) return 0;
        if (pivot != i) {
            for (int j = 0; j < 6; ++j) {
                double t = n[i][j];
                n[i][j] = n[pivot][j];
                n[pivot][j] = t;
            }
            for (int c = 0; c < 3; ++c) {
                double t = v[i][c];
                v[i][c] = v[pivot][c];
                v[pivot][c] = t;
            }
        }
        for (int r = i + 1; r < 6; ++r) {
            double f = n[r][i] / n[i][i];
            for (int j = i; j < 6; ++j) n[r][j] -= f * n[i][j];
            for (int c = 0; c < 3; ++c) v[r][c] -= f * v[i][c];
        }
    }
    double solution[6][3];
    for (int i = 5; i >= 0; --i)
        for (int c = 0; c < 3; ++c) {
            double value = v[i][c];
            for (int j = i + 1; j < 6; ++j) value -= n[i][j] * solution[j][c];
            solution[i][c] = value / n[i][i];
        }
    for (int c = 0; c < 3; ++c) out[c] = solution[0][c] * scale[0];
    return 1;
}

/* The filtered gathered radiance of pixel (x, y) (its record p; the fields in `near`), into out. */
static void filter_pixel(const rad_renderer *r, const rad_gather_pixel *pixels,
                         const filter_neighbours *near, int x, int y, double out[3]) {
    const rad_view *view = &r->view;
    const int width = view->width, height = view->height;
    const size_t own = (size_t)y * width + x;
    const rad_gather_pixel *p = &pixels[own];
    /* The window: as many pixels as the radius covers at p's depth, at most MAX_PIXELS. */
    double depth = (p->position[0] - view->eye.x) * view->forward.x +
                   (p->position[1] - view->eye.y) * view->forward.y +
                   (p->position[2] - view->eye.z) * view->forward.z;
    if (!(depth > 0)) { /* behind the eye: cannot be, but then the pixel keeps its own */
        for (int c = 0; c < 3; ++c) out[c] = p->reflected[c];
        return;
    }
    /* No absolute lengths below: a scene in any unit filters alike (tests/cli_units.sh). */
    double pixel_size = 2 * view->tan_half_fov * depth / height;
    double least = fmin(fmax(FLOOR_REACH * p->distance, FEWEST_PIXELS * pixel_size),
                        MIN_PIXELS * pixel_size);
    double reach = fmax(RADIUS * p->distance, least) / pixel_size;
    int k = reach < MAX_PIXELS ? (int)reach : MAX_PIXELS;
    /* h = max(A min(R_p, R_q), least), so 1 / h^2 = min(max(1 / (A R_p)^2, 1 / (A R_q)^2),
     * 1 / least^2): no division per neighbour. */
    const float inverse_least2 = (float)(1 / (least * least));
    const float px = near->x[own], py = near->y[own], pz = near->z[own];
    const float p_inverse = near->inverse_reach2[own];
    const uint32_t polygon = near->polygon[own];
    /* Weighted moments m[a][b] = sum w dx^a dy^b (a + b <= 4) and r[a][b][c] = sum w I_c dx^a
     * dy^b (a + b <= 2): along each row in single precision, FILTER_LANES neighbours at once,
     * in powers of dx; the row's lanes summed in double and folded in with its dy. The pixel
     * is one of its own neighbours (weight 1, dx = dy = 0). */
    double m[5][5] = {{0}}, rhs[3][3][3] = {{{0}}};
    int y0 = y - k < 0 ? 0 : y - k, y1 = y + k >= height ? height - 1 : y + k;
    int x0 = x - k < 0 ? 0 : x - k, x1 = x + k >= width ? width - 1 : x + k;
    for (int qy = y0; qy <= y1; ++qy) {
        float a[5][FILTER_LANES] = {{0}}, b[3][3][FILTER_LANES] = {{{0}}};
        const size_t row = (size_t)qy * width;
        const float *qx_ = near->x + row, *qy_ = near->y + row, *qz_ = near->z + row;
        const float *qinv = near->inverse_reach2 + row;
        const float *i0 = near->reflected[0] + row, *i1 = near->reflected[1] + row,
                    *i2 = near->reflected[2] + row;
        const uint32_t *qpolygon = near->polygon + row;
        for (int base = x0; base <= x1; base += FILTER_LANES)
            for (int l = 0; l < FILTER_LANES; ++l) {
                const int q = base + l;
                float ex = qx_[q] - px, ey = qy_[q] - py, ez = qz_[q] - pz;
                float d2 = ex * ex + ey * ey + ez * ez;
                /* Ternaries, not fminf / fmaxf: those are calls under C11's strict floating
                 * point. */
                float inverse_h2 = p_inverse > qinv[q] ? p_inverse : qinv[q];
                inverse_h2 = inverse_h2 < inverse_least2 ? inverse_h2 : inverse_least2;
                float t2 = d2 * inverse_h2;
                /* Bitwise, and a product rather than a choice: a branch (a conditional
                 * multiplication is one under C11's trapping floating point) keeps the lanes
                 * from running together. */
                int weighs = (q <= x1) & (qpolygon[q] == polygon) & (t2 < 1);
                float far = 1 - t2;
                float w = (float)weighs * far * far, dx = (float)(q - x);
                float wx = w * dx, wxx = wx * dx, wxxx = wxx * dx;
                a[0][l] += w;
                a[1][l] += wx;
                a[2][l] += wxx;
                a[3][l] += wxxx;
                a[4][l] += wxxx * dx;
                b[0][0][l] += w * i0[q];
                b[0][1][l] += w * i1[q];
                b[0][2][l] += w * i2[q];
                b[1][0][l] += wx * i0[q];
                b[1][1][l] += wx * i1[q];
                b[1][2][l] += wx * i2[q];
                b[2][0][l] += wxx * i0[q];
                b[2][1][l] += wxx * i1[q];
                b[2][2][l] += wxx * i2[q];
            }
        /* The lanes summed pairwise (halves, quarters, eighths), all sums at once. */
        for (int width_ = FILTER_LANES / 2; width_ >= 1; width_ /= 2) {
            for (int i = 0; i < 5; ++i)
                for (int l = 0; l < width_; ++l) a[i][l] += a[i][l + width_];
            for (int i = 0; i < 3; ++i)
                for (int c = 0; c < 3; ++c)
                    for (int l = 0; l < width_; ++l) b[i][c][l] += b[i][c][l + width_];
        }
        double sa[5], sb[3][3];
        for (int i = 0; i < 5; ++i) sa[i] = a[i][0];
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) sb[i][c] = b[i][c][0];
        if (!(sa[0] > 0)) continue;
        double dy = qy - y, dy_power[5] = {1, dy, dy * dy, dy * dy * dy, dy * dy * dy * dy};
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; i + j <= 4; ++j) m[i][j] += sa[i] * dy_power[j];
        for (int i = 0; i <= 2; ++i)
            for (int j = 0; i + j <= 2; ++j)
                for (int c = 0; c < 3; ++c) rhs[i][j][c] += sb[i][c] * dy_power[j];
    }
    for (int c = 0; c < 3; ++c) out[c] = rhs[0][0][c] / m[0][0];
    if (fit_quadric(m, rhs, out)) return;
    /* The plane a + b dx + c dy (a line or a point of pixels, or too few for the quadric): the
     * normal equations [s0 sx sy; sx sxx sxy; sy sxy syy] (a b c) = (si six siy), solved by
     * Cramer's rule; a determinant small against its scale means the window is a line or a
     * point, and the plain mean stays. */
    double s0 = m[0][0], sx = m[1][0], sy = m[0][1], sxx = m[2][0], sxy = m[1][1], syy = m[0][2];
    double det = s0 * (sxx * syy - sxy * sxy) - sx * (sx * syy - sxy * sy) + sy * (sx * sxy - sxx * sy);
    double scale = s0 * sxx * syy;
    if (!(scale > 0) || !(det > 1e-3 * scale)) return;
    for (int c = 0; c < 3; ++c) {
        double si = rhs[0][0][c], six = rhs[1][0][c], siy = rhs[0][1][c];
        double value = si * (sxx * syy - sxy * sxy) - sx * (six * syy - sxy * siy) +
                       sy * (six * sxy - sxx * siy);
        out[c] = value / det;
    }
}

rad_status rad_gather_filter(const rad_renderer *r, const rad_gather_pixel *pixels, float *image) {
    const int width = r->view.width, height = r->view.height;
    size_t count = (size_t)width * height, padded = count + FILTER_LANES;
    float *change = rad_alloc(r->ctx, count * 3, sizeof *change);
    float *fields = rad_alloc_zero(r->ctx, padded * 7, sizeof *fields);
    uint32_t *polygon = rad_alloc(r->ctx, padded, sizeof *polygon);
    if (!change || !fields || !polygon) {
        rad_free(r->ctx, change);
        rad_free(r->ctx, fields);
        rad_free(r->ctx, polygon);
        return RAD_ERROR_NO_MEMORY;
    }
    filter_neighbours near = {fields, fields + padded, fields + 2 * padded, fields + 3 * padded,
                              {fields + 4 * padded, fields + 5 * padded, fields + 6 * padded},
                              polygon};
    for (size_t i = count; i < padded; ++i) polygon[i] = RAD_RENDER_NO_POLYGON;
    for (size_t i = 0; i < count; ++i) {
        const rad_gather_pixel *p = &pixels[i];
        polygon[i] = p->polygon;
        double reach = RADIUS * p->distance;
        near.inverse_reach2[i] = reach > 0 ? (float)fmin(1 / (reach * reach), FLT_MAX) : FLT_MAX;
        near.x[i] = p->position[0];
        near.y[i] = p->position[1];
        near.z[i] = p->position[2];
        for (int c = 0; c < 3; ++c) near.reflected[c][i] = p->reflected[c];
    }
#pragma omp parallel for schedule(dynamic, 4) num_threads(rad_thread_count(r->ctx))
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            size_t i = (size_t)y * width + x;
            const rad_gather_pixel *p = &pixels[i];
            change[3 * i] = change[3 * i + 1] = change[3 * i + 2] = 0;
            if (p->polygon == RAD_RENDER_NO_POLYGON) continue;
            double filtered[3];
            filter_pixel(r, pixels, &near, x, y, filtered);
            for (int c = 0; c < 3; ++c)
                change[3 * i + c] = (float)(p->rho[c] * (filtered[c] - p->reflected[c]));
        }
    for (size_t i = 0; i < count * 3; ++i) image[i] = fmaxf(0.0f, image[i] + change[i]);
    rad_free(r->ctx, change);
    rad_free(r->ctx, fields);
    rad_free(r->ctx, polygon);
    return RAD_OK;
}
