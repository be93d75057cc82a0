/* hemicube.c - form factors with the hemicube (Cohen & Greenberg 1985, "The hemi-cube: a
 * radiosity solution for complex environments").
 *
 * Around the centre of the shooting patch stands half a cube: a top face of R x R pixels facing
 * along the patch normal and four side faces of R x R/2 pixels. Every element of the mesh is
 * projected onto the faces and scan-converted into a z-buffer with an item buffer of element
 * ids, so each pixel keeps the nearest element in its direction: visibility comes from the
 * z-buffer of the element mesh itself, not from rays. A pixel at (a, b) on the top face (cube
 * half-width 1, at distance 1) carries the delta form factor
 *     dF = dA / (pi (a^2 + b^2 + 1)^2),      side face at height c:  dF = c dA / (pi (a^2 + c^2 + 1)^2),
 * here computed exactly per pixel with the contour integral (analytic.c), so they sum to 1.
 * F(patch -> element) is the sum of dF over the element's pixels: whole rows at once, as
 * progressive refinement wants them (Cohen et al. 1988).
 *
 * The cube is turned about the normal by a random angle for each shooting patch (seeded by the
 * context seed and the patch), which breaks the aliasing of regular meshes against the regular
 * pixel grid. Elements whose back faces the patch centre hide what is behind them but receive
 * nothing.
 *
 * Work is split into 12 tiles (the top face in quadrants, each side in halves), rasterised in
 * parallel; each pixel's delta form factor is added to its element in 2^-60 fixed point, so the
 * sums do not depend on the order, the tiling or the thread count. */

#include "formfactor/geometric.h"

#include "core/team.h"

#include <stdatomic.h>
#include <string.h>

#define FIXED_ONE 1152921504606846976.0 /* 2^60 */
#define TILE_COUNT 12
#define MAX_CLIP 16

typedef struct tile {
    int face;           /* 0 top, 1..4 sides */
    int i0, i1, j0, j1; /* pixel range */
} tile;

typedef struct hemicube_provider {
    rad_ff_common common;
    int resolution, side_height;
    int64_t *top_ff, *side_ff; /* delta form factors in fixed point */
    float *depth[5];           /* 1 / distance along the face axis; larger is nearer */
    int32_t *item[5];          /* element ids, -1 for none */
    tile tiles[TILE_COUNT];
    double *local;             /* vertices in the hemicube frame, 3 per vertex */
    uint32_t *outcode;         /* per vertex: 5 bits per face, the view-volume planes it is
                                  outside of */
    uint8_t *faces;            /* per element: bit f set when it may show on face f */
    uint8_t *clip;             /* per element: bit f set when face f must clip it */
    uint8_t *receives;         /* per element: its front faces the patch centre */
    int threads;
    int64_t *sums;             /* threads x element_count */
} hemicube_provider;

/* Face f's coordinates of a point in the hemicube frame: a, b across the face, d along its
 * axis. Top: (x, y, z); sides look along +x, -x, +y, -y with b = z up. */
static inline void face_coords(int f, const double *p, double *a, double *b, double *d) {
    switch (f) {
    case 0: *a = p[0]; *b = p[1]; *d = p[2]; break;
    case 1: *a = p[1]; *b = p[2]; *d = p[0]; break;
    case 2: *a = -p[1]; *b = p[2]; *d = -p[0]; break;
    case 3: *a = -p[0]; *b = p[2]; *d = p[1]; break;
    default: *a = p[0]; *b = p[2]; *d = -p[1]; break;
    }
}

static inline double min2(double a, double b) { return a < b ? a : b; }
static inline double max2(double a, double b) { return a > b ? a : b; }

typedef struct clip_vertex {
    double a, b, d;
} clip_vertex;

/* The five half-spaces of a face's view volume, as values that must be >= 0. */
static inline double clip_value(int f, int plane, const clip_vertex *v, double near) {
    switch (plane) {
    case 0: return v->d - v->a;
    case 1: return v->d + v->a;
    case 2: return v->d - v->b;
    case 3: return f == 0 ? v->d + v->b : v->b;
    default: return v->d - near;
    }
}

static int clip_polygon(int f, int plane, const clip_vertex *in, int n, clip_vertex *out,
                        double near) {
    int kept = 0;
    for (int i = 0; i < n; ++i) {
        const clip_vertex *p = &in[i], *q = &in[(i + 1) % n];
        double vp = clip_value(f, plane, p, near), vq = clip_value(f, plane, q, near);
        if (vp >= 0) out[kept++] = *p;
        if ((vp >= 0) != (vq >= 0) && kept < MAX_CLIP) {
            double t = vp / (vp - vq);
            out[kept++] = (clip_vertex){p->a + t * (q->a - p->a), p->b + t * (q->b - p->b),
                                        p->d + t * (q->d - p->d)};
        }
        if (kept >= MAX_CLIP - 1) break;
    }
    return kept;
}

/* The view-volume planes of every face that a point in the hemicube frame is outside of. */
static uint32_t vertex_outcode(const double *p, double near) {
    uint32_t code = 0;
    for (int f = 0; f < 5; ++f) {
        clip_vertex v;
        face_coords(f, p, &v.a, &v.b, &v.d);
        for (int plane = 0; plane < 5; ++plane)
            if (clip_value(f, plane, &v, near) < 0) code |= 1u << (5 * f + plane);
    }
    return code;
}

/* Scan-converts element e into tile t: clip to the face's view volume, project, fill the spans
 * of the convex polygon, keep the nearest element per pixel. */
static void rasterise(hemicube_provider *h, const tile *t, size_t e, double near) {
    const rad_mesh *mesh = h->common.c.mesh;
    const int f = t->face, R = h->resolution;
    const uint32_t *corner = mesh->element_vertices[e];
    clip_vertex buffer[2][MAX_CLIP];
    int n = rad_mesh_corner_count(mesh, e), current = 0;
    for (int k = 0; k < n; ++k) {
        clip_vertex *v = &buffer[0][k];
        face_coords(f, h->local + 3 * (size_t)corner[k], &v->a, &v->b, &v->d);
    }
    if (h->clip[e] & (1u << f)) {
        uint32_t violated = 0;
        for (int k = 0; k < n; ++k) violated |= h->outcode[corner[k]] >> (5 * f);
        for (int plane = 0; plane < 5 && n >= 3; ++plane)
            if (violated & (1u << plane)) {
                n = clip_polygon(f, plane, buffer[current], n, buffer[1 - current], near);
                current = 1 - current;
            }
        if (n < 3) return;
    }
    const clip_vertex *poly = buffer[current];

    /* Project to pixel coordinates: x = (a/d + 1) R/2, y = (b/d + 1) R/2 (top) or b/d R/2.
     * Most elements of a fine mesh are small: give up at once when no pixel centre of the tile
     * falls in their bounds. */
    const double half = 0.5 * R, y_shift = f == 0 ? 1.0 : 0.0;
    double x[MAX_CLIP], y[MAX_CLIP];
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < n; ++i) {
        double inverse = 1.0 / poly[i].d;
        x[i] = (poly[i].a * inverse + 1.0) * half;
        y[i] = (poly[i].b * inverse + y_shift) * half;
        xmin = min2(xmin, x[i]);
        xmax = max2(xmax, x[i]);
        ymin = min2(ymin, y[i]);
        ymax = max2(ymax, y[i]);
    }
    int jmin = (int)ceil(ymin - 0.5), jmax = (int)floor(ymax - 0.5);
    int imin_box = (int)ceil(xmin - 0.5), imax_box = (int)floor(xmax - 0.5);
    if (jmin < t->j0) jmin = t->j0;
    if (jmax > t->j1 - 1) jmax = t->j1 - 1;
    if (imin_box < t->i0) imin_box = t->i0;
    if (imax_box > t->i1 - 1) imax_box = t->i1 - 1;
    if (jmin > jmax || imin_box > imax_box) return;
    double area = 0;
    for (int i = 0; i < n; ++i) area += x[i] * y[(i + 1) % n] - x[(i + 1) % n] * y[i];
    if (fabs(area) < 1e-12) return;
    const double orientation = area > 0 ? 1.0 : -1.0;

    /* Depth: on the element's plane N . P = k, 1 / d is affine in the screen coordinates. */
    double na, nb, nd, normal[3] = {0, 0, 0};
    {
        /* The element normal in the hemicube frame, from its corners. */
        const double *p0 = h->local + 3 * (size_t)mesh->element_vertices[e][0];
        const double *p1 = h->local + 3 * (size_t)mesh->element_vertices[e][1];
        const double *p2 = h->local + 3 * (size_t)mesh->element_vertices[e][2];
        double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        double v[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        normal[0] = u[1] * v[2] - u[2] * v[1];
        normal[1] = u[2] * v[0] - u[0] * v[2];
        normal[2] = u[0] * v[1] - u[1] * v[0];
    }
    face_coords(f, normal, &na, &nb, &nd);
    double k = na * poly[0].a + nb * poly[0].b + nd * poly[0].d;
    double scale = fabs(na) + fabs(nb) + fabs(nd);
    if (!(fabs(k) > 1e-12 * scale * (fabs(poly[0].a) + fabs(poly[0].b) + fabs(poly[0].d))))
        return; /* seen edge on */

    /* 1/d at pixel centre (px, py): (na alpha + nb beta + nd) / k with alpha = px / half - 1,
     * beta = py / half - y_shift. */
    const double wx = na / (k * half), wy = nb / (k * half);
    const double w0 = (-na + nb * -y_shift + nd) / k;

    /* Edges as bounds on x along a scanline: inside is orientation * (dx (py - y_i) -
     * dy (px - x_i)) >= 0, so an edge with orientation * dy < 0 bounds x from below, one with
     * orientation * dy > 0 from above, and a horizontal one keeps or drops the whole row. */
    double edge_x[MAX_CLIP], edge_y[MAX_CLIP], edge_slope[MAX_CLIP], flat_dx[MAX_CLIP];
    int lower[MAX_CLIP], upper[MAX_CLIP], flat[MAX_CLIP], nl = 0, nu = 0, nf = 0;
    for (int i = 0; i < n; ++i) {
        int i1 = i + 1 < n ? i + 1 : 0;
        double dx = x[i1] - x[i], dy = y[i1] - y[i];
        edge_x[i] = x[i];
        edge_y[i] = y[i];
        if (dy * orientation < 0) lower[nl++] = i;
        else if (dy * orientation > 0) upper[nu++] = i;
        else {
            flat[nf++] = i;
            flat_dx[i] = dx * orientation;
            continue;
        }
        edge_slope[i] = dx / dy;
    }

    float *depth = h->depth[f];
    int32_t *item = h->item[f];
    const int32_t id = (int32_t)e;
    for (int j = jmin; j <= jmax; ++j) {
        double py = j + 0.5, lo = xmin, hi = xmax;
        int empty = 0;
        for (int k = 0; k < nf; ++k)
            if (flat_dx[flat[k]] * (py - edge_y[flat[k]]) < 0) empty = 1;
        if (empty) continue;
        for (int k = 0; k < nl; ++k) {
            int i = lower[k];
            lo = max2(lo, edge_x[i] + (py - edge_y[i]) * edge_slope[i]);
        }
        for (int k = 0; k < nu; ++k) {
            int i = upper[k];
            hi = min2(hi, edge_x[i] + (py - edge_y[i]) * edge_slope[i]);
        }
        int imin = (int)ceil(lo - 0.5), imax = (int)floor(hi - 0.5);
        if (imin < t->i0) imin = t->i0;
        if (imax > t->i1 - 1) imax = t->i1 - 1;
        float *depth_row = depth + (size_t)j * (size_t)R;
        int32_t *item_row = item + (size_t)j * (size_t)R;
        const float w_row = (float)(w0 + wy * py + 0.5 * wx), w_step = (float)wx;
        /* Branch-free so it vectorises: keep the nearer of what is there and this element. */
        for (int i = imin; i <= imax; ++i) {
            float w = w_row + w_step * (float)i, old = depth_row[i];
            int nearer = w > old;
            depth_row[i] = nearer ? w : old;
            item_row[i] = nearer ? id : item_row[i];
        }
    }
}

/* One row's work, shared out to the context's worker threads (core/team.h), which sleep
 * between rows where an OpenMP region per row left them spinning. */
typedef struct hemicube_job {
    hemicube_provider *h;
    const rad_mesh *mesh;
    float *row;
    rad_vec3 t, b, normal, centre;
    double near;
    size_t first, last; /* the shooting patch's own elements */
    long n, nv;
    _Atomic uint64_t receivers;
} hemicube_job;

#define HEMICUBE_CHUNK 1024 /* vertices or elements per task of the per-element loops */

/* Vertices into the hemicube frame, with their outcodes. */
static void frame_vertices(void *user, long chunk, int worker) {
    (void)worker;
    hemicube_job *job = user;
    hemicube_provider *h = job->h;
    long end = (chunk + 1) * HEMICUBE_CHUNK < job->nv ? (chunk + 1) * HEMICUBE_CHUNK : job->nv;
    for (long v = chunk * HEMICUBE_CHUNK; v < end; ++v) {
        rad_vec3 d = v3_sub(job->mesh->vertices[v], job->centre);
        double *local = h->local + 3 * v;
        local[0] = v3_dot(d, job->t);
        local[1] = v3_dot(d, job->b);
        local[2] = v3_dot(d, job->normal);
        h->outcode[v] = vertex_outcode(local, job->near);
    }
}

/* Which faces each element may show on, which must clip it, whether it receives. */
static void classify_elements(void *user, long chunk, int worker) {
    (void)worker;
    hemicube_job *job = user;
    hemicube_provider *h = job->h;
    const rad_mesh *mesh = job->mesh;
    uint64_t receivers = 0;
    long end = (chunk + 1) * HEMICUBE_CHUNK < job->n ? (chunk + 1) * HEMICUBE_CHUNK : job->n;
    for (long e = chunk * HEMICUBE_CHUNK; e < end; ++e) {
        if ((size_t)e >= job->first && (size_t)e < job->last) {
            h->faces[e] = 0;
            h->clip[e] = 0;
            h->receives[e] = 0;
            continue;
        }
        /* Face f shows e unless all corners are outside one of its planes; it must clip e
         * when some corner is outside some plane. */
        const uint32_t *corner = mesh->element_vertices[e];
        uint32_t all = h->outcode[corner[0]], any = all;
        for (int k = 1; k < rad_mesh_corner_count(mesh, (size_t)e); ++k) {
            all &= h->outcode[corner[k]];
            any |= h->outcode[corner[k]];
        }
        uint8_t faces = 0, clip = 0;
        for (int f = 0; f < 5; ++f) {
            if (!((all >> (5 * f)) & 0x1f)) faces |= (uint8_t)(1u << f);
            if ((any >> (5 * f)) & 0x1f) clip |= (uint8_t)(1u << f);
        }
        h->faces[e] = faces;
        h->clip[e] = clip;
        h->receives[e] = h->faces[e] &&
                         v3_dot(mesh->element_normal[e],
                                v3_sub(job->centre, mesh->element_centroid[e])) > 0;
        receivers += h->receives[e];
    }
    atomic_fetch_add_explicit(&job->receivers, receivers, memory_order_relaxed);
}

/* One tile: clear it, rasterise every element that may show on its face, and add each pixel's
 * delta form factor to the worker's own fixed-point sums. */
static void rasterise_tile(void *user, long k, int worker) {
    hemicube_job *job = user;
    hemicube_provider *h = job->h;
    const int R = h->resolution;
    const tile *tl = &h->tiles[k];
    const int f = tl->face;
    int64_t *sums = h->sums + (size_t)worker * (size_t)job->n;
    for (int j = tl->j0; j < tl->j1; ++j) {
        memset(h->depth[f] + (size_t)j * R + tl->i0, 0, (size_t)(tl->i1 - tl->i0) * sizeof(float));
        for (int i = tl->i0; i < tl->i1; ++i) h->item[f][(size_t)j * R + i] = -1;
    }
    for (long e = 0; e < job->n; ++e)
        if (h->faces[e] & (1u << f)) rasterise(h, tl, (size_t)e, job->near);
    const int64_t *ff = f == 0 ? h->top_ff : h->side_ff;
    for (int j = tl->j0; j < tl->j1; ++j)
        for (int i = tl->i0; i < tl->i1; ++i) {
            int32_t id = h->item[f][(size_t)j * R + i];
            if (id >= 0 && h->receives[id]) sums[id] += ff[(size_t)j * R + i];
        }
}

/* Add the workers' fixed-point sums: exact, so independent of who did what. */
static void add_sums(void *user, long chunk, int worker) {
    (void)worker;
    hemicube_job *job = user;
    hemicube_provider *h = job->h;
    const size_t n = (size_t)job->n;
    long end = (chunk + 1) * HEMICUBE_CHUNK < job->n ? (chunk + 1) * HEMICUBE_CHUNK : job->n;
    for (long e = chunk * HEMICUBE_CHUNK; e < end; ++e) {
        int64_t total = 0;
        for (int k = 0; k < h->threads; ++k) {
            total += h->sums[(size_t)k * n + (size_t)e];
            h->sums[(size_t)k * n + (size_t)e] = 0;
        }
        job->row[e] = (float)((double)total / FIXED_ONE);
    }
}

static rad_status hemicube_row(rad_ff_provider *self, size_t patch, float *row) {
    hemicube_provider *h = (hemicube_provider *)self;
    const rad_ff_context *c = &h->common.c;
    const rad_mesh *mesh = c->mesh;
    const rad_ff_patch *p = &c->patches[patch];
    hemicube_job job = {.h = h, .mesh = mesh, .row = row};
    job.n = (long)mesh->element_count;
    job.nv = (long)mesh->vertex_count;
    job.first = mesh->patch_first[patch];
    job.last = mesh->patch_first[patch + 1];
    job.near = 1e-12 * sqrt(p->area);
    atomic_init(&job.receivers, 0);

    /* The frame: the patch normal and a random turn about it. */
    rad_rng rng = rad_rng_make(rad_ff_row_seed(c, patch), 0);
    double angle = 2 * RAD_PI * rad_rng_uniform(&rng);
    rad_vec3 t0, b0;
    job.normal = p->normal;
    job.centre = p->centre;
    v3_basis(job.normal, &t0, &b0);
    job.t = v3_add(v3_scale(t0, cos(angle)), v3_scale(b0, sin(angle)));
    job.b = v3_cross(job.normal, job.t);

    rad_context *ctx = c->ctx;
    const long vertex_chunks = (job.nv + HEMICUBE_CHUNK - 1) / HEMICUBE_CHUNK;
    const long element_chunks = (job.n + HEMICUBE_CHUNK - 1) / HEMICUBE_CHUNK;
    rad_team_for(ctx, vertex_chunks, frame_vertices, &job);
    rad_team_for(ctx, element_chunks, classify_elements, &job);
    rad_team_for(ctx, TILE_COUNT, rasterise_tile, &job);
    rad_team_for(ctx, element_chunks, add_sums, &job);
    h->common.stats.rows++;
    h->common.stats.receivers += atomic_load(&job.receivers);
    return RAD_OK;
}

static void hemicube_destroy(rad_ff_provider *self) {
    hemicube_provider *h = (hemicube_provider *)self;
    rad_context *ctx = h->common.c.ctx;
    rad_free(ctx, h->top_ff);
    rad_free(ctx, h->side_ff);
    for (int f = 0; f < 5; ++f) {
        rad_free(ctx, h->depth[f]);
        rad_free(ctx, h->item[f]);
    }
    rad_free(ctx, h->local);
    rad_free(ctx, h->outcode);
    rad_free(ctx, h->faces);
    rad_free(ctx, h->clip);
    rad_free(ctx, h->receives);
    rad_free(ctx, h->sums);
    rad_ff_common_destroy(&h->common);
}

/* Exact delta form factors: the contour integral of each pixel seen from the cube's centre. */
static void delta_form_factors(hemicube_provider *h) {
    const int R = h->resolution, H = h->side_height;
    const double step = 2.0 / R;
    const rad_vec3 origin = v3(0, 0, 0), up = v3(0, 0, 1);
#pragma omp parallel for schedule(static) num_threads(h->threads)
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < R; ++i) {
            double a0 = -1 + i * step, a1 = a0 + step, b0 = -1 + j * step, b1 = b0 + step;
            /* Clockwise seen from above, so the pixel faces down towards the centre. */
            rad_vec3 top[4] = {v3(a0, b0, 1), v3(a0, b1, 1), v3(a1, b1, 1), v3(a1, b0, 1)};
            h->top_ff[(size_t)j * R + i] = llround(rad_ff_point_polygon(origin, up, top, 4) * FIXED_ONE);
            if (j < H) {
                double c0 = j * step, c1 = c0 + step;
                /* The side face x = 1 (face 1: a = y, b = z), facing -x. */
                rad_vec3 side[4] = {v3(1, a0, c0), v3(1, a0, c1), v3(1, a1, c1), v3(1, a1, c0)};
                h->side_ff[(size_t)j * R + i] =
                    llround(rad_ff_point_polygon(origin, up, side, 4) * FIXED_ONE);
            }
        }
}

rad_status rad_ff_hemicube_create(const rad_ff_context *context, rad_ff_provider **out) {
    rad_context *ctx = context->ctx;
    int R = context->options.hemicube_resolution;
    if (R < 2) R = 2;
    R += R & 1; /* even, so the side faces are exactly R/2 high */
    const int H = R / 2;
    const size_t top = (size_t)R * (size_t)R, side = (size_t)R * (size_t)H;
    const size_t n = context->mesh->element_count;
    const int threads = rad_thread_count(ctx);
    double bytes = (double)(top + 4 * side) * 8 + (double)(top + side) * 8 +
                   (double)context->mesh->vertex_count * 28 + (double)n * (2 + 8.0 * threads);
    rad_status status = rad_check_budget(ctx, bytes, "the hemicube");
    if (status) return status;

    rad_ff_common *common;
    status = rad_ff_common_create(context, sizeof(hemicube_provider), "hemicube", hemicube_row,
                                  hemicube_destroy, &common);
    if (status) return status;
    hemicube_provider *h = (hemicube_provider *)common;
    h->resolution = R;
    h->side_height = H;
    h->threads = threads;
    h->top_ff = rad_alloc(ctx, top, sizeof *h->top_ff);
    h->side_ff = rad_alloc(ctx, side, sizeof *h->side_ff);
    int ok = h->top_ff && h->side_ff;
    for (int f = 0; f < 5 && ok; ++f) {
        size_t pixels = f == 0 ? top : side;
        h->depth[f] = rad_alloc(ctx, pixels, sizeof *h->depth[f]);
        h->item[f] = rad_alloc(ctx, pixels, sizeof *h->item[f]);
        ok = h->depth[f] && h->item[f];
    }
    h->local = rad_alloc(ctx, 3 * (context->mesh->vertex_count ? context->mesh->vertex_count : 1),
                         sizeof *h->local);
    h->outcode = rad_alloc(ctx, context->mesh->vertex_count ? context->mesh->vertex_count : 1,
                           sizeof *h->outcode);
    h->faces = rad_alloc(ctx, n ? n : 1, sizeof *h->faces);
    h->clip = rad_alloc(ctx, n ? n : 1, sizeof *h->clip);
    h->receives = rad_alloc(ctx, n ? n : 1, sizeof *h->receives);
    h->sums = rad_alloc_zero(ctx, (size_t)threads * (n ? n : 1), sizeof *h->sums);
    if (!ok || !h->local || !h->outcode || !h->faces || !h->clip || !h->receives || !h->sums) {
        /* The caller (rad_ff_create) releases the shared context on failure: not here too. */
        h->common.c.rays = NULL, h->common.c.patches = NULL, h->common.c.shaft = NULL;
        h->common.c.element_radius = NULL;
        hemicube_destroy(&h->common.base);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for a %d-pixel hemicube", R);
    }
    /* Tiles: the top face in quadrants, each side face in halves. */
    int k = 0;
    for (int q = 0; q < 4; ++q)
        h->tiles[k++] = (tile){0, (q & 1) * H, (q & 1) * H + H, (q >> 1) * H, (q >> 1) * H + H};
    for (int f = 1; f <= 4; ++f)
        for (int half = 0; half < 2; ++half)
            h->tiles[k++] = (tile){f, half * H, half * H + H, 0, H};
    delta_form_factors(h);
    *out = &h->common.base;
    return RAD_OK;
}

/* The registration (factory.c lists it). */
static const rad_method_option hemicube_options[] = {
    {"hemicube-res", "pixels along the top face (256)"},
};
const rad_ff_method_entry rad_ff_method_hemicube = {
    {"hemicube", "projection onto a hemicube of z-buffered faces (Cohen & Greenberg 1985)", 0, hemicube_options, sizeof hemicube_options / sizeof hemicube_options[0]},
    256,
    rad_ff_hemicube_create,
};
