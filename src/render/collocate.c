/* collocate.c - the direct light of the smooth bare solution evaluated at the element corners
 * (point collocation, as Lischinski, Tampieri and Greenberg 1992 evaluate the radiosity at the
 * mesh's vertices; docs/rendering.md, "Direct light at the corners").
 *
 * Averaging the elements around a vertex (reconstruct.c) stands for the value half an element
 * away: on a shadow's edge the one row of umbra is pulled towards the penumbra, and a cut along
 * the shadow boundary (discontinuity meshing) cannot help, since the vertex on the cut still
 * takes the mean of both sides. The direct light is what changes fast; the light reflected
 * once more is smooth. So, when the solution itself is shown (no final gather):
 *
 *   1. D(x): the direct light at a point, in radiance units (rho times the irradiance over pi
 *      is added later), from the emitting leaves (unoccluded: Lambert's contour integral,
 *      rad_ff_point_polygon; times the share of a fixed stratified set of points on the emitter
 *      that x sees, each weighted by its kernel cos cos / r^2) and from the point, spot and
 *      directional lights (one shadow ray each).
 *   2. Each element's value minus the mean of its corners' light (the mean of the picture
 *      drawn over it; the light at its centroid before, which misplaced a large hierarchy
 *      leaf's light at a shadow's edge) is what the element holds besides that light (its
 *      emission, and what the evaluations miss): that part is averaged at the vertices as
 *      before (and fitted on boundaries).
 *   3. Each corner of each element: that average plus rho D at a point just inside the element
 *      from the corner. Corners of neighbouring elements are evaluated apart, so a value jump
 *      (a contact, a point light's hard shadow) stays sharp where an element edge lies on it,
 *      and the kinks of an area light's penumbra lie on element edges where D1 cut them.
 *
 * Every point is evaluated on its own with the same emitter points, so the result does not
 * depend on the thread count. The rays are bounded (COLLOCATE_RAYS): past the budget fewer
 * points per emitter, then only the brightest emitters (the others stay in the average). */
#include "render/render.h"

#include "core/rng.h"
#include "formfactor/pair.h"
#include "light/lights.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Visibility points over all the emitters used, at most (a grid of g x g per emitting leaf). */
#define COLLOCATE_SAMPLES 64
/* Shadow rays for one picture's corners, at most. */
#define COLLOCATE_RAYS 16000000.0
/* Gather rays per point: a COLLOCATE_GATHER x COLLOCATE_GATHER stratified set, at most. */
#define COLLOCATE_GATHER 16
/* An emitter past the budget keeps its light in the gather (gather_at) where the gather rays
 * are expected to hit its lamp at least this often from the point. */
#define GATHER_HITS 2.0

typedef struct emitter_leaf {
    uint32_t element;
    double power;
} emitter_leaf;

typedef struct collocation {
    const rad_renderer *r;
    size_t emitter_count;
    uint32_t *emitter; /* emitting leaves used */
    rad_vec3 (*corners)[4];
    int *corner_count;
    float (*radiance)[3]; /* emitted radiance of each, L = E / pi (the material's own) */
    rad_vec3 *points;     /* emitter_count * per_emitter visibility points */
    int per_emitter;
    uint8_t *used;        /* per leaf: an emitter whose light direct_at gives */
    float *lamp_area;     /* per emitting leaf: the area of the emitting polygon it is part of */
    int gather_grid;      /* gather rays: a gather_grid x gather_grid stratified set */
    double ambient[3];    /* the display's ambient radiosity / pi (zero unless asked for) */
} collocation;

/* An emitting leaf and the input polygon it was cut from (collocation_make's lamp areas). */
typedef struct polygon_leaf {
    uint32_t polygon, element;
} polygon_leaf;

static int by_polygon(const void *x, const void *y) {
    const polygon_leaf *a = x, *b = y;
    if (a->polygon != b->polygon) return a->polygon < b->polygon ? -1 : 1;
    return a->element < b->element ? -1 : a->element > b->element;
}

static int by_power(const void *x, const void *y) {
    const emitter_leaf *a = x, *b = y;
    if (a->power != b->power) return a->power > b->power ? -1 : 1;
    return a->element < b->element ? -1 : a->element > b->element;
}

/* The direct light at x (normal n) from the emitters and the lights: radiance a white diffuse
 * surface would reflect, irradiance / pi. */
static void direct_at(const collocation *c, rad_vec3 x, rad_vec3 n, double out[3]) {
    const rad_renderer *r = c->r;
    out[0] = out[1] = out[2] = 0;
    for (size_t j = 0; j < c->emitter_count; ++j) {
        double factor = rad_ff_point_polygon(x, n, c->corners[j], c->corner_count[j]);
        if (!(factor > 0)) continue;
        /* Visibility: the kernel-weighted share of the emitter's points seen from x. */
        const rad_vec3 *p = c->points + j * (size_t)c->per_emitter;
        double seen = 0, all = 0;
        rad_vec3 front = r->mesh->element_normal[c->emitter[j]];
        for (int s = 0; s < c->per_emitter; ++s) {
            rad_vec3 d = v3_sub(p[s], x);
            double d2 = v3_dot(d, d);
            double w = d2 > 0 ? fmax(0, v3_dot(n, d)) * fmax(0, -v3_dot(front, d)) / (d2 * d2) : 0;
            if (!(w > 0)) continue;
            all += w;
            if (!rad_element_rays_occluded(r->rays, x, p[s])) seen += w;
        }
        if (!(all > 0)) continue;
        double visible = seen / all;
        /* Irradiance pi L F; reflected radiance of a white surface L F. */
        for (int k = 0; k < 3; ++k) out[k] += c->radiance[j][k] * factor * visible;
    }
    for (size_t l = 0; l < r->light_count; ++l) {
        rad_light_arrival arrival;
        if (!rad_light_arrive(&r->lights[l], x, &arrival)) continue;
        double cosine = v3_dot(n, arrival.direction);
        if (!(cosine > 0)) continue;
        if (isfinite(arrival.distance)) {
            if (rad_element_rays_occluded(r->rays, x, v3_add(x, v3_scale(arrival.direction, arrival.distance))))
                continue;
        } else {
            rad_element_hit hit;
            if (rad_element_rays_intersect(r->rays, x, arrival.direction, r->rays->epsilon, INFINITY, &hit))
                continue;
        }
        for (int k = 0; k < 3; ++k) out[k] += arrival.irradiance[k] * cosine / RAD_PI;
    }
}

/* The light reflected onto x once more: the solution's radiance B / pi where cosine-distributed
 * rays (the same stratified set at every point, in the frame of the normal) meet it, or the sky
 * where they leave the scene; the mean over the rays is irradiance / pi. Without the emission of
 * the emitters direct_at counts, and of those past the ray budget whose lamp the rays would
 * rarely find from x (GATHER_HITS): that light stays in the average (step 2). Counted here
 * it was their direct light estimated by a few rays per corner, each corner its own: the 841
 * lamps of office 100000 (1.26 M corners: one lamp within the budget, 16 gather rays a corner)
 * drew bright and dark blotches of a metre or more over its bare walls and floor. A lamp the rays
 * find often (Sponza's sky, one polygon cut into many leaves) keeps its light here: in the
 * average its shadows were lost (16x16 blocks 6.6% -> 7.6%). Whatever the rule counts, step 2
 * takes its mean over the element's corners back out of the element's value, so the element
 * keeps its light either way; the rule only decides where that light is drawn sharp. */
static void gather_at(const collocation *c, rad_vec3 x, rad_vec3 n, double out[3]) {
    const rad_renderer *r = c->r;
    rad_vec3 t, b;
    v3_basis(n, &t, &b);
    int g = c->gather_grid;
    double sum[3] = {0, 0, 0};
    rad_rng rng = rad_rng_make(0x67617468ull, 0);
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
            double su = (i + rad_rng_uniform(&rng)) / g, sv = (j + rad_rng_uniform(&rng)) / g;
            double radius = sqrt(su), phi = 2 * RAD_PI * sv;
            rad_vec3 d = v3_add(v3_add(v3_scale(t, radius * cos(phi)), v3_scale(b, radius * sin(phi))),
                                v3_scale(n, sqrt(fmax(0, 1 - su))));
            rad_element_hit hit;
            double l[3];
            if (!rad_element_rays_intersect(r->rays, x, d, r->rays->epsilon, INFINITY, &hit)) {
                rad_sky_radiance(&r->sky, d, l);
            } else {
                /* The back of a surface shows what its front reflects, as in the final gather
                 * (only fronts emit). */
                rad_reconstruct_gather_radiance(r, hit.element, hit.u, hit.v, l);
                /* The rays' expected hits on the hit leaf's lamp from x, g^2 times its
                 * projected solid angle over pi. */
                double hits = (double)(g * g) * c->lamp_area[hit.element] *
                              fabs(v3_dot(r->mesh->element_normal[hit.element], d)) *
                              sqrt(fmax(0, 1 - su)) / (RAD_PI * hit.t * hit.t);
                if (c->used[hit.element] || !hit.front || !(hits >= GATHER_HITS)) {
                    const double *own = rad_renderer_material(r, hit.element)->emission;
                    for (int k = 0; k < 3; ++k)
                        l[k] = fmax(0, l[k] - fmin(own[k], r->element_emission[hit.element][k]));
                }
            }
            for (int k = 0; k < 3; ++k) sum[k] += l[k];
        }
    for (int k = 0; k < 3; ++k) out[k] = sum[k] / (g * g) + c->ambient[k];
}

/* Step 1's emitters: the emitting leaves by power, as many as the ray budget allows for
 * `points` evaluation points; their visibility points. */
static rad_status collocation_make(const rad_renderer *r, size_t points, collocation *c) {
    rad_context *ctx = r->ctx;
    const rad_mesh *mesh = r->mesh;
    memset(c, 0, sizeof *c);
    c->r = r;
    size_t count = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const double *own = rad_renderer_material(r, (uint32_t)e)->emission;
        count += own[0] > 0 || own[1] > 0 || own[2] > 0;
    }
    emitter_leaf *leaves = rad_alloc(ctx, count + 1, sizeof *leaves);
    if (!leaves) return RAD_ERROR_NO_MEMORY;
    count = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        const double *own = rad_renderer_material(r, (uint32_t)e)->emission;
        if (!(own[0] > 0 || own[1] > 0 || own[2] > 0)) continue;
        double power = (own[0] + own[1] + own[2]) * mesh->element_area[e];
        if (!(power > 0) || !isfinite(power)) continue;
        leaves[count++] = (emitter_leaf){(uint32_t)e, power};
    }
    /* Each emitting leaf's lamp area: the leaves grouped by input polygon, their areas summed. */
    c->lamp_area = rad_alloc_zero(ctx, mesh->element_count + 1, sizeof *c->lamp_area);
    polygon_leaf *grouped = rad_alloc(ctx, count + 1, sizeof *grouped);
    if (!c->lamp_area || !grouped) {
        rad_free(ctx, grouped);
        rad_free(ctx, leaves);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t j = 0; j < count; ++j)
        grouped[j] = (polygon_leaf){mesh->element_polygon[leaves[j].element], leaves[j].element};
    qsort(grouped, count, sizeof *grouped, by_polygon);
    for (size_t first = 0, end; first < count; first = end) {
        double area = 0;
        for (end = first; end < count && grouped[end].polygon == grouped[first].polygon; ++end)
            area += mesh->element_area[grouped[end].element];
        for (size_t j = first; j < end; ++j) c->lamp_area[grouped[j].element] = (float)area;
    }
    rad_free(ctx, grouped);
    qsort(leaves, count, sizeof *leaves, by_power);
    /* Points per emitter: a g x g grid, COLLOCATE_SAMPLES over all of them; fewer emitters
     * (the brightest) when even one point each is over the budget. */
    double budget = COLLOCATE_RAYS / (double)(points ? points : 1);
    /* Half the budget for the gather, half for the emitters' visibility. */
    int gather = (int)floor(sqrt(fmin((double)(COLLOCATE_GATHER * COLLOCATE_GATHER), 0.5 * budget)));
    c->gather_grid = gather < 4 ? 4 : gather;
    budget = fmax(1, budget - (double)(c->gather_grid * c->gather_grid));
    if ((double)count > budget) count = (size_t)budget;
    int grid = count ? (int)ceil(sqrt((double)COLLOCATE_SAMPLES / (double)count)) : 1;
    while (grid > 1 && (double)(count * (size_t)grid * (size_t)grid) > budget) grid--;
    c->per_emitter = grid * grid;
    c->emitter_count = count;
    c->used = rad_alloc_zero(ctx, mesh->element_count + 1, 1);
    c->emitter = rad_alloc(ctx, count + 1, sizeof *c->emitter);
    c->corners = rad_alloc(ctx, count + 1, sizeof *c->corners);
    c->corner_count = rad_alloc(ctx, count + 1, sizeof *c->corner_count);
    c->radiance = rad_alloc(ctx, count + 1, sizeof *c->radiance);
    c->points = rad_alloc(ctx, count * (size_t)c->per_emitter + 1, sizeof *c->points);
    if (r->settings.ambient) {
        r->solution->ops->ambient(r->solution, c->ambient);
        for (int k = 0; k < 3; ++k) c->ambient[k] /= RAD_PI;
    }
    if (!c->used || !c->emitter || !c->corners || !c->corner_count || !c->radiance || !c->points) {
        rad_free(ctx, leaves);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t j = 0; j < count; ++j) {
        uint32_t e = leaves[j].element;
        c->emitter[j] = e;
        c->used[e] = 1;
        c->corner_count[j] = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < c->corner_count[j]; ++k)
            c->corners[j][k] = mesh->vertices[mesh->element_vertices[e][k]];
        const double *own = rad_renderer_material(r, e)->emission;
        for (int k = 0; k < 3; ++k) c->radiance[j][k] = fminf((float)own[k], r->element_emission[e][k]);
        /* A jittered grid on the leaf, fixed per leaf (the same for every receiving point). */
        rad_rng rng = rad_rng_make(0x636f6c6cull, e);
        for (int a = 0; a < grid; ++a)
            for (int b = 0; b < grid; ++b) {
                double s = (a + rad_rng_uniform(&rng)) / grid, t = (b + rad_rng_uniform(&rng)) / grid;
                if (c->corner_count[j] == 3) { /* the square onto the triangle */
                    double root = sqrt(s);
                    s = root * (1 - t);
                    t = root * t;
                }
                c->points[j * (size_t)c->per_emitter + (size_t)(a * grid + b)] = rad_element_point(mesh, e, s, t);
            }
    }
    rad_free(ctx, leaves);
    return RAD_OK;
}

static void collocation_free(rad_context *ctx, collocation *c) {
    rad_free(ctx, c->emitter);
    rad_free(ctx, c->corners);
    rad_free(ctx, c->corner_count);
    rad_free(ctx, c->radiance);
    rad_free(ctx, c->points);
    rad_free(ctx, c->used);
    rad_free(ctx, c->lamp_area);
}

int rad_collocate_wanted(const rad_renderer *r) {
    return r->settings.final_gather == 0 && r->settings.shading != RAD_SHADING_FLAT;
}

rad_status rad_collocate_light(rad_renderer *r, float (*corner)[4][3]) {
    rad_context *ctx = r->ctx;
    const rad_mesh *mesh = r->mesh;
    size_t n = mesh->element_count;
    size_t points = 0;
    for (size_t e = 0; e < n; ++e) points += (size_t)rad_mesh_corner_count(mesh, e);
    collocation c;
    rad_status status = collocation_make(r, points, &c);
    if (status) {
        collocation_free(ctx, &c);
        return status;
    }
    long long count = (long long)n;
#pragma omp parallel for schedule(dynamic, 16) num_threads(rad_thread_count(ctx))
    for (long long i = 0; i < count; ++i) {
        size_t e = (size_t)i;
        rad_vec3 normal = mesh->element_normal[e], centre = mesh->element_centroid[e];
        const float *rho = r->element_reflectance[e];
        int corners = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < corners; ++k) {
            rad_vec3 vertex = mesh->vertices[mesh->element_vertices[e][k]];
            rad_vec3 at = v3_lerp(vertex, centre, RAD_CORNER_INSET);
            double direct[3], reflected[3];
            direct_at(&c, at, normal, direct);
            gather_at(&c, at, normal, reflected);
            float *out = corner[e][k];
            for (int ch = 0; ch < 3; ++ch) out[ch] = (float)(rho[ch] * (direct[ch] + reflected[ch]));
        }
    }
    collocation_free(ctx, &c);
    return RAD_OK;
}
