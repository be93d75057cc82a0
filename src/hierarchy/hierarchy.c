/* hierarchy.c - quadtrees over the input polygons, links between their nodes, the refinement
 * oracle and the gather/push-pull solve of hierarchical radiosity (Hanrahan, Salzman &
 * Aupperle 1991). See hierarchy.h for the method and docs/hierarchical.md for the parameters. */
#include "hierarchy/hierarchy.h"

#include "formfactor/geometric.h"
#include "scene/rays.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEFAULT_LINK_ERROR 1e-3
#define DEFAULT_MIN_AREA 1e-6
#define MAX_DEPTH 24
#define PARALLEL_MIN 256 /* loops shorter than this run on one thread */

typedef double rgb[3];

struct rad_hier {
    rad_context *ctx;
    const rad_scene *scene;
    rad_rays *rays;
    rad_hier_node *nodes;
    size_t node_count, node_capacity, root_count;
    uint32_t *polygon_root_first, *polygon_root_count;
    rgb *reflectance, *emission; /* per polygon */
    rad_vec3 *normal;            /* per polygon */
    rad_hier_link *links;
    size_t link_count;
    /* Links are sorted by receiver: group g's links are receivers' group_first[g] .. [g+1]. */
    size_t group_count;
    size_t *group_first;
    double threshold; /* absolute power: link_error times the power emitted */
    double emission_max, emitted_power;
    double min_area;  /* absolute */
    rad_hier_stats stats;
};

static int threads(const rad_hier *h) { return rad_thread_count(h->ctx); }

/* ---- Nodes ------------------------------------------------------------------------------- */

static double corners_area(const rad_vec3 *c, int count) {
    if (count == 3) return 0.5 * v3_length(v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0])));
    return 0.5 * v3_length(v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1])));
}

static rad_status reserve_nodes(rad_hier *h, size_t extra) {
    if (h->node_count + extra <= h->node_capacity) return RAD_OK;
    size_t wanted = h->node_capacity ? h->node_capacity : 64;
    while (wanted < h->node_count + extra) wanted *= 2;
    rad_hier_node *grown = rad_realloc(h->ctx, h->nodes, wanted, sizeof *grown);
    if (!grown) return RAD_ERROR_NO_MEMORY;
    h->nodes = grown;
    h->node_capacity = wanted;
    return RAD_OK;
}

static void init_node(rad_hier *h, rad_hier_node *n, const rad_vec3 *c, int count,
                      uint32_t polygon, uint32_t root, int depth) {
    memset(n, 0, sizeof *n);
    for (int k = 0; k < count; ++k) n->corner[k] = c[k];
    n->corner_count = (uint8_t)count;
    n->area = corners_area(c, count);
    n->polygon = polygon;
    n->root = root;
    n->first_child = RAD_HIER_NO_NODE;
    n->depth = (uint8_t)depth;
    memcpy(n->radiosity, h->emission[polygon], sizeof n->radiosity);
}

/* Splits a leaf into four: a quad at its edge midpoints and centre, a triangle at its edge
 * midpoints (the fourth child is the middle triangle). Children keep the winding. */
static rad_status subdivide(rad_hier *h, uint32_t index) {
    if (h->nodes[index].first_child != RAD_HIER_NO_NODE) return RAD_OK;
    rad_status status = reserve_nodes(h, 4);
    if (status) return status;
    rad_hier_node parent = h->nodes[index];
    const rad_vec3 *c = parent.corner;
    rad_vec3 child[4][4];
    int count = parent.corner_count;
    if (count == 4) {
        rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5);
        rad_vec3 m23 = v3_lerp(c[2], c[3], 0.5), m30 = v3_lerp(c[3], c[0], 0.5);
        rad_vec3 m = v3_scale(v3_add(v3_add(c[0], c[1]), v3_add(c[2], c[3])), 0.25);
        const rad_vec3 q[4][4] = {{c[0], m01, m, m30}, {m01, c[1], m12, m},
                                  {m, m12, c[2], m23}, {m30, m, m23, c[3]}};
        memcpy(child, q, sizeof child);
    } else {
        rad_vec3 m01 = v3_lerp(c[0], c[1], 0.5), m12 = v3_lerp(c[1], c[2], 0.5);
        rad_vec3 m20 = v3_lerp(c[2], c[0], 0.5);
        const rad_vec3 t[4][4] = {{c[0], m01, m20, m20}, {m01, c[1], m12, m12},
                                  {m20, m12, c[2], c[2]}, {m12, m20, m01, m01}};
        memcpy(child, t, sizeof child);
    }
    uint32_t first = (uint32_t)h->node_count;
    for (int k = 0; k < 4; ++k) {
        init_node(h, &h->nodes[first + k], child[k], count, parent.polygon, parent.root,
                  parent.depth + 1);
        memcpy(h->nodes[first + k].radiosity, parent.radiosity, sizeof parent.radiosity);
    }
    h->node_count += 4;
    h->nodes[index].first_child = first;
    return RAD_OK;
}

/* The receiver's quadrature points: the 2 x 2 Gauss rule in the quad's bilinear parameters, or
 * the three-point rule (2/3, 1/6, 1/6) of a triangle. */
static int quadrature_points(const rad_hier_node *n, rad_vec3 *out) {
    const rad_vec3 *c = n->corner;
    if (n->corner_count == 3) {
        for (int k = 0; k < 3; ++k)
            out[k] = v3_add(v3_scale(c[k], 2.0 / 3), v3_scale(v3_add(c[(k + 1) % 3], c[(k + 2) % 3]),
                                                            1.0 / 6));
        return 3;
    }
    const double g = 0.5 - 0.5 / sqrt(3.0);
    const double uv[4][2] = {{g, g}, {1 - g, g}, {1 - g, 1 - g}, {g, 1 - g}};
    for (int k = 0; k < 4; ++k) {
        double u = uv[k][0], v = uv[k][1];
        out[k] = v3_add(v3_add(v3_scale(c[0], (1 - u) * (1 - v)), v3_scale(c[1], u * (1 - v))),
                        v3_add(v3_scale(c[2], u * v), v3_scale(c[3], (1 - u) * v)));
    }
    return 4;
}

/* ---- Links ------------------------------------------------------------------------------- */

/* Nonzero when some corner of `n` lies strictly in front of the plane through `p` with normal
 * `normal`. */
static int any_in_front(const rad_hier_node *n, rad_vec3 p, rad_vec3 normal) {
    for (int k = 0; k < n->corner_count; ++k)
        if (v3_dot(normal, v3_sub(n->corner[k], p)) > 0) return 1;
    return 0;
}

/* The link receiver <- source: its form factor and error bound. Returns 0 when no light can
 * pass (the two face away from each other). */
static int make_link(const rad_hier *h, uint32_t receiver, uint32_t source, rad_hier_link *out) {
    const rad_hier_node *r = &h->nodes[receiver], *s = &h->nodes[source];
    if (r->polygon == s->polygon) return 0;
    rad_vec3 nr = h->normal[r->polygon], ns = h->normal[s->polygon];
    if (!any_in_front(s, r->corner[0], nr) || !any_in_front(r, s->corner[0], ns)) return 0;
    rad_vec3 x[4], y[4];
    int rn = quadrature_points(r, x), sn = quadrature_points(s, y);
    /* Lambert's contour integral from each receiver point to the source polygon. */
    double sum = 0, lo = INFINITY, hi = 0;
    for (int i = 0; i < rn; ++i) {
        double f = rad_ff_point_polygon(x[i], nr, s->corner, s->corner_count);
        sum += f;
        lo = fmin(lo, f);
        hi = fmax(hi, f);
    }
    double form_factor = sum / rn;
    if (!(form_factor > 0)) return 0;
    /* The spread also looks at the corners (pulled in a little, off neighbouring planes): the
     * kernel peaks at edges shared with the source, where the quadrature points see least. */
    rad_vec3 centre = v3_scale(v3_add(v3_add(r->corner[0], r->corner[1]),
                                      v3_add(r->corner[2], r->corner[r->corner_count - 1])), 0.25);
    if (r->corner_count == 3)
        centre = v3_scale(v3_add(v3_add(r->corner[0], r->corner[1]), r->corner[2]), 1.0 / 3);
    for (int k = 0; k < r->corner_count; ++k) {
        double f = rad_ff_point_polygon(v3_lerp(r->corner[k], centre, 0.01), nr, s->corner,
                                        s->corner_count);
        lo = fmin(lo, f);
        hi = fmax(hi, f);
    }
    /* Visibility: a ray from every receiver point to every source point. */
    rad_vec3 a[16] = {{0, 0, 0}}, b[16] = {{0, 0, 0}};
    uint8_t occluded[16];
    int count = 0;
    for (int i = 0; i < rn; ++i)
        for (int j = 0; j < sn; ++j) {
            a[count] = x[i];
            b[count] = y[j];
            ++count;
        }
    rad_rays_occluded_batch(h->rays, a, b, (size_t)count, occluded);
    int visible = 0;
    for (int i = 0; i < count; ++i) visible += !occluded[i];
    /* Rays that all hit something do not prove the pair hidden (a sliver of the receiver may
     * see past the occluder): such a link carries nothing but keeps its whole factor as its
     * error, so the oracle refines it where it matters. */
    double fraction = (double)visible / count;
    int partial = visible < count;
    double error = 0.25 * (hi - lo) * fraction + (partial ? form_factor : 0);
    out->receiver = receiver;
    out->source = source;
    out->form_factor = (float)(form_factor * fraction);
    /* The sign keeps whether the visibility was partial. */
    out->error = (float)(partial ? -error : error);
    return 1;
}

static int can_split(const rad_hier *h, const rad_hier_node *n) {
    return n->area > h->min_area && n->depth < MAX_DEPTH;
}

/* The oracle: 0 keeps the link, 1 splits its receiver, 2 its source. *relative is its error
 * over the threshold. */
static int decide(const rad_hier *h, const rad_hier_link *link, double *relative) {
    const rad_hier_node *r = &h->nodes[link->receiver], *s = &h->nodes[link->source];
    const double *rho = h->reflectance[r->polygon];
    double carried = 0;
    for (int c = 0; c < 3; ++c) carried = fmax(carried, rho[c] * s->radiosity[c]);
    double error = carried * fabs((double)link->error) * r->area;
    *relative = error / h->threshold;
    if (!(error > h->threshold)) return 0;
    int partial = link->error < 0;
    int split_r = can_split(h, r), split_s = can_split(h, s);
    /* The receiver is split first: that is what puts leaves at shadow edges and contacts.
     * A receiver already much smaller than its source passes a partly hidden link to the
     * source's children instead (the penumbra is the source's to resolve). */
    if (split_r && !(partial && split_s && s->area > r->area)) return 1;
    if (partial && split_s) return 2;
    return 0;
}

/* Sorts `links` by receiver (stable) into h->links and rebuilds the receiver groups. Takes
 * ownership of `links`. */
static rad_status adopt_links(rad_hier *h, rad_hier_link *links, size_t count) {
    rad_context *ctx = h->ctx;
    size_t *start = rad_alloc_zero(ctx, h->node_count + 1, sizeof *start);
    rad_hier_link *sorted = rad_alloc(ctx, count ? count : 1, sizeof *sorted);
    size_t *groups = NULL;
    if (!start || !sorted) goto fail;
    for (size_t i = 0; i < count; ++i) start[links[i].receiver + 1]++;
    size_t group_count = 0;
    for (size_t n = 0; n < h->node_count; ++n) {
        group_count += start[n + 1] > 0;
        start[n + 1] += start[n];
    }
    groups = rad_alloc(ctx, group_count + 1, sizeof *groups);
    if (!groups) goto fail;
    group_count = 0;
    for (size_t n = 0; n < h->node_count; ++n)
        if (start[n + 1] > start[n]) groups[group_count++] = start[n];
    groups[group_count] = count;
    for (size_t i = 0; i < count; ++i) sorted[start[links[i].receiver]++] = links[i];
    rad_free(ctx, start);
    rad_free(ctx, links);
    rad_free(ctx, h->links);
    rad_free(ctx, h->group_first);
    h->links = sorted;
    h->link_count = count;
    h->group_first = groups;
    h->group_count = group_count;
    h->stats.links = count;
    return RAD_OK;
fail:
    rad_free(ctx, start);
    rad_free(ctx, sorted);
    rad_free(ctx, links);
    return RAD_ERROR_NO_MEMORY;
}

static rad_status check_memory(rad_hier *h, size_t links, size_t nodes) {
    char what[160];
    snprintf(what, sizeof what, "hierarchical radiosity with %zu links and %zu nodes", links, nodes);
    double bytes = 2.0 * (double)links * sizeof(rad_hier_link) + (double)nodes * sizeof(rad_hier_node);
    return rad_check_budget(h->ctx, bytes, what);
}

rad_status rad_hier_link_roots(rad_hier *h) {
    size_t n = h->root_count;
    rad_status status = check_memory(h, n * n, h->node_count);
    if (status) return status;
    size_t pairs = n * n > 0 ? n * n : 1;
    rad_hier_link *all = rad_alloc(h->ctx, pairs, sizeof *all);
    uint8_t *made = rad_alloc_zero(h->ctx, pairs, 1);
    if (!all || !made) {
        rad_free(h->ctx, all);
        rad_free(h->ctx, made);
        return RAD_ERROR_NO_MEMORY;
    }
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads(h)) if (n >= 16)
    for (long i = 0; i < (long)n; ++i)
        for (size_t j = 0; j < n; ++j)
            if ((size_t)i != j)
                made[(size_t)i * n + j] = (uint8_t)make_link(h, (uint32_t)i, (uint32_t)j,
                                                             &all[(size_t)i * n + j]);
    size_t kept = 0;
    for (size_t i = 0; i < n * n; ++i)
        if (made[i]) all[kept++] = all[i];
    rad_free(h->ctx, made);
    return adopt_links(h, all, kept);
}

rad_status rad_hier_refine(rad_hier *h) {
    rad_context *ctx = h->ctx;
    size_t n = h->link_count;
    uint8_t *decision = rad_alloc(ctx, n ? n : 1, 1);
    if (!decision) return RAD_ERROR_NO_MEMORY;
    double largest = 0;
    size_t splits = 0;
    /* The oracle over every link, with the current radiosities. */
#pragma omp parallel for schedule(static) num_threads(threads(h)) if (n >= PARALLEL_MIN) \
    reduction(max : largest) reduction(+ : splits)
    for (long i = 0; i < (long)n; ++i) {
        double relative;
        decision[i] = (uint8_t)decide(h, &h->links[i], &relative);
        largest = fmax(largest, relative);
        splits += decision[i] != 0;
    }
    h->stats.largest_error = largest;
    h->stats.refined = splits;
    if (splits == 0) {
        rad_free(ctx, decision);
        return RAD_OK;
    }
    rad_status status = check_memory(h, n + 3 * splits, h->node_count + 4 * splits);
    if (status == RAD_ERROR_MEMORY_BUDGET) {
        /* Keep the solution so far: say why refinement stopped, then stop refining. */
        rad_warn(ctx, "%s; refinement stops at %zu links, keeping the solution so far",
                 rad_context_error(ctx), n);
        h->stats.refined = 0;
        h->stats.budget_reached = 1;
        rad_free(ctx, decision);
        return RAD_OK;
    }
    rad_hier_link *next = NULL;
    uint8_t *made = NULL;
    if (!status) {
        next = rad_alloc(ctx, n + 4 * splits, sizeof *next);
        made = rad_alloc(ctx, 4 * splits, 1);
        if (!next || !made) status = RAD_ERROR_NO_MEMORY;
    }
    /* Kept links first, then the children's candidate links, in link order. */
    size_t kept = 0, candidates = 0;
    for (size_t i = 0; i < n && !status; ++i)
        if (!decision[i]) next[kept++] = h->links[i];
    for (size_t i = 0; i < n && !status; ++i) {
        if (!decision[i]) continue;
        rad_hier_link link = h->links[i];
        uint32_t split = decision[i] == 1 ? link.receiver : link.source;
        if ((status = subdivide(h, split))) break;
        uint32_t first = h->nodes[split].first_child;
        for (uint32_t k = 0; k < 4; ++k) {
            rad_hier_link *c = &next[kept + candidates++];
            c->receiver = decision[i] == 1 ? first + k : link.receiver;
            c->source = decision[i] == 1 ? link.source : first + k;
        }
    }
    rad_free(ctx, decision);
    if (status) {
        rad_free(ctx, next);
        rad_free(ctx, made);
        return status;
    }
    /* The new links' form factors, in parallel (each writes its own slot). */
    rad_hier_link *fresh = next + kept;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (candidates >= 64)
    for (long i = 0; i < (long)candidates; ++i)
        made[i] = (uint8_t)make_link(h, fresh[i].receiver, fresh[i].source, &fresh[i]);
    size_t count = kept;
    for (size_t i = 0; i < candidates; ++i)
        if (made[i]) next[count++] = fresh[i];
    rad_free(ctx, made);
    return adopt_links(h, next, count);
}

/* ---- Solving ----------------------------------------------------------------------------- */

/* Pushes irradiance down to the leaves (adding what each level gathered), sets the leaves'
 * radiosity E + rho H, and pulls area-weighted means back up. Returns the largest change of a
 * leaf's radiosity. */
static double push_pull(rad_hier *h, uint32_t index, const double down[3]) {
    rad_hier_node *n = &h->nodes[index];
    double total[3];
    for (int c = 0; c < 3; ++c) total[c] = down[c] + n->irradiance[c];
    double change = 0;
    if (n->first_child == RAD_HIER_NO_NODE) {
        const double *rho = h->reflectance[n->polygon], *e = h->emission[n->polygon];
        for (int c = 0; c < 3; ++c) {
            double b = e[c] + rho[c] * total[c];
            change = fmax(change, fabs(b - n->radiosity[c]));
            n->radiosity[c] = b;
        }
        return change;
    }
    double sum[3] = {0, 0, 0}, area = 0;
    for (uint32_t k = 0; k < 4; ++k) {
        uint32_t child = n->first_child + k;
        change = fmax(change, push_pull(h, child, total));
        const rad_hier_node *m = &h->nodes[child];
        for (int c = 0; c < 3; ++c) sum[c] += m->radiosity[c] * m->area;
        area += m->area;
    }
    n = &h->nodes[index];
    for (int c = 0; c < 3; ++c) n->radiosity[c] = area > 0 ? sum[c] / area : 0;
    return change;
}

rad_status rad_hier_solve(rad_hier *h, double tolerance, int max_rounds) {
    const long groups = (long)h->group_count, roots = (long)h->root_count;
    const long nodes = (long)h->node_count;
    double limit = tolerance * (h->emission_max > 0 ? h->emission_max : 1);
    int round = 0;
    for (round = 1; round <= max_rounds; ++round) {
        /* Gather: every receiver sums its links in their fixed order. */
#pragma omp parallel num_threads(threads(h)) if (nodes >= PARALLEL_MIN)
        {
#pragma omp for schedule(static)
            for (long i = 0; i < nodes; ++i) memset(h->nodes[i].irradiance, 0, sizeof(double[3]));
#pragma omp for schedule(dynamic, 64)
            for (long g = 0; g < groups; ++g) {
                double sum[3] = {0, 0, 0};
                size_t first = h->group_first[g], last = h->group_first[g + 1];
                for (size_t l = first; l < last; ++l) {
                    const rad_hier_link *link = &h->links[l];
                    const double *b = h->nodes[link->source].radiosity;
                    for (int c = 0; c < 3; ++c) sum[c] += (double)link->form_factor * b[c];
                }
                memcpy(h->nodes[h->links[first].receiver].irradiance, sum, sizeof sum);
            }
        }
        /* Push-pull, one tree per task. */
        double change = 0;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads(h)) if (roots >= 64) \
    reduction(max : change)
        for (long r = 0; r < roots; ++r) {
            const double zero[3] = {0, 0, 0};
            change = fmax(change, push_pull(h, (uint32_t)r, zero));
        }
        if (change <= limit) break;
        if (rad_progress(h->ctx, "hierarchical gathering", round, max_rounds))
            return rad_fail(h->ctx, RAD_ERROR_CANCELLED, "cancelled after %d gathering rounds",
                            round);
    }
    h->stats.solve_rounds = round > max_rounds ? max_rounds : round;
    return RAD_OK;
}

/* ---- Set-up and queries ------------------------------------------------------------------ */

rad_status rad_hier_create(rad_context *ctx, const rad_scene *scene,
                           const rad_hier_options *options, rad_hier **out) {
    *out = NULL;
    rad_hier_options o = options ? *options : (rad_hier_options){0};
    if (o.link_error < 0 || !isfinite(o.link_error))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the link error must be a positive number, not %g", o.link_error);
    if (o.link_error == 0) o.link_error = DEFAULT_LINK_ERROR;
    if (!(o.min_area >= 0) || !isfinite(o.min_area))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "bad minimum node area %g", o.min_area);
    if (o.min_area == 0) o.min_area = DEFAULT_MIN_AREA;
    rad_hier *h = rad_alloc_zero(ctx, 1, sizeof *h);
    if (!h) return RAD_ERROR_NO_MEMORY;
    h->ctx = ctx;
    h->scene = scene;
    size_t np = scene->polygon_count;
    h->polygon_root_first = rad_alloc_zero(ctx, np + 1, sizeof *h->polygon_root_first);
    h->polygon_root_count = rad_alloc_zero(ctx, np + 1, sizeof *h->polygon_root_count);
    h->reflectance = rad_alloc_zero(ctx, np + 1, sizeof *h->reflectance);
    h->emission = rad_alloc_zero(ctx, np + 1, sizeof *h->emission);
    h->normal = rad_alloc_zero(ctx, np + 1, sizeof *h->normal);
    rad_status status = RAD_OK;
    if (!h->polygon_root_first || !h->polygon_root_count || !h->reflectance || !h->emission ||
        !h->normal)
        status = RAD_ERROR_NO_MEMORY;
    double total_area = 0;
    for (size_t p = 0; p < np && !status; ++p) {
        const rad_polygon *polygon = &scene->polygons[p];
        const rad_material *m = &scene->materials[scene->surfaces[polygon->surface].material];
        for (int c = 0; c < 3; ++c) {
            h->reflectance[p][c] = m->reflectance[c];
            h->emission[p][c] = RAD_PI * m->emission[c];
            h->emission_max = fmax(h->emission_max, h->emission[p][c]);
        }
        double emitted = fmax(h->emission[p][0], fmax(h->emission[p][1], h->emission[p][2]));
        h->normal[p] = rad_polygon_normal(scene, polygon);
        h->polygon_root_first[p] = (uint32_t)h->node_count;
        if (!(rad_polygon_area(scene, polygon) > 0)) continue;
        /* Quads and triangles are roots; larger polygons are fanned into triangles. */
        uint32_t roots = polygon->count <= 4 ? 1 : polygon->count - 2;
        if ((status = reserve_nodes(h, roots))) break;
        for (uint32_t k = 0; k < roots; ++k) {
            rad_vec3 c[4];
            int count = polygon->count == 4 ? 4 : 3;
            if (polygon->count <= 4)
                for (int i = 0; i < count; ++i) c[i] = rad_polygon_vertex(scene, polygon, (uint32_t)i);
            else {
                c[0] = rad_polygon_vertex(scene, polygon, 0);
                c[1] = rad_polygon_vertex(scene, polygon, k + 1);
                c[2] = rad_polygon_vertex(scene, polygon, k + 2);
            }
            rad_hier_node *n = &h->nodes[h->node_count];
            init_node(h, n, c, count, (uint32_t)p, (uint32_t)h->node_count, 0);
            if (!(n->area > 0)) continue;
            total_area += n->area;
            h->emitted_power += emitted * n->area;
            h->node_count++;
            h->polygon_root_count[p]++;
        }
    }
    h->root_count = h->node_count;
    h->min_area = o.min_area * total_area;
    h->threshold = o.link_error * (h->emitted_power > 0 ? h->emitted_power : 1);
    if (!status && h->root_count == 0)
        status = rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                          "%s: no polygon with a nonzero area", scene->source);
    if (!status) status = rad_rays_create(ctx, scene, &h->rays);
    if (status) {
        rad_hier_destroy(h);
        return status;
    }
    h->stats.roots = h->root_count;
    *out = h;
    return RAD_OK;
}

void rad_hier_destroy(rad_hier *h) {
    if (!h) return;
    rad_context *ctx = h->ctx;
    rad_rays_destroy(h->rays);
    rad_free(ctx, h->nodes);
    rad_free(ctx, h->polygon_root_first);
    rad_free(ctx, h->polygon_root_count);
    rad_free(ctx, h->reflectance);
    rad_free(ctx, h->emission);
    rad_free(ctx, h->normal);
    rad_free(ctx, h->links);
    rad_free(ctx, h->group_first);
    rad_free(ctx, h);
}

rad_hier_stats rad_hier_get_stats(const rad_hier *h) {
    rad_hier_stats s = h->stats;
    s.nodes = h->node_count;
    s.leaves = 0;
    for (size_t i = 0; i < h->node_count; ++i) s.leaves += h->nodes[i].first_child == RAD_HIER_NO_NODE;
    s.links = h->link_count;
    s.roots = h->root_count;
    return s;
}

const rad_hier_node *rad_hier_nodes(const rad_hier *h, size_t *count) {
    *count = h->node_count;
    return h->nodes;
}

const rad_hier_link *rad_hier_links(const rad_hier *h, size_t *count) {
    *count = h->link_count;
    return h->links;
}

uint32_t rad_hier_polygon_roots(const rad_hier *h, uint32_t polygon, uint32_t *count) {
    *count = polygon < h->scene->polygon_count ? h->polygon_root_count[polygon] : 0;
    return *count ? h->polygon_root_first[polygon] : RAD_HIER_NO_NODE;
}

uint32_t rad_hier_root_of(const rad_hier *h, uint32_t node) { return h->nodes[node].root; }

/* How far x is inside node n (the smallest distance to an edge, negative outside). */
static double inside(const rad_hier *h, const rad_hier_node *n, rad_vec3 x) {
    rad_vec3 normal = h->normal[n->polygon];
    double worst = INFINITY;
    for (int k = 0; k < n->corner_count; ++k) {
        rad_vec3 a = n->corner[k], b = n->corner[(k + 1) % n->corner_count];
        rad_vec3 edge = v3_sub(b, a);
        double length = v3_length(edge);
        if (!(length > 0)) continue;
        worst = fmin(worst, v3_dot(v3_cross(edge, v3_sub(x, a)), normal) / length);
    }
    return worst;
}

void rad_hier_radiosity_at(const rad_hier *h, uint32_t polygon, rad_vec3 x, double out[3]) {
    uint32_t count, index = rad_hier_polygon_roots(h, polygon, &count);
    if (index == RAD_HIER_NO_NODE) {
        memset(out, 0, sizeof(double[3]));
        return;
    }
    double best = -INFINITY;
    uint32_t first = index;
    for (uint32_t k = 0; k < count; ++k) {
        double d = inside(h, &h->nodes[first + k], x);
        if (d > best) best = d, index = first + k;
    }
    while (h->nodes[index].first_child != RAD_HIER_NO_NODE) {
        uint32_t child = h->nodes[index].first_child, pick = child;
        best = -INFINITY;
        for (uint32_t k = 0; k < 4; ++k) {
            double d = inside(h, &h->nodes[child + k], x);
            if (d > best) best = d, pick = child + k;
        }
        index = pick;
    }
    memcpy(out, h->nodes[index].radiosity, sizeof(double[3]));
}
