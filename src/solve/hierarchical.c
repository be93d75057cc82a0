/* hierarchical.c - the hierarchical solver (Hanrahan, Salzman & Aupperle 1991; src/hierarchy):
 * begin builds the quadtree roots over the input polygons, links every pair of roots and
 * solves; each step is one pass of the oracle over the links followed by a new solve, until no
 * link is refined or by the tail rule (the residual is the oracle's largest error, in the
 * units of the link error). After every
 * step the hierarchy is evaluated at the system's elements (the mean of the leaves under five
 * points of each element), so rendering, baking and solution files read it like any other
 * solution. */
#include "solve/solver.h"

#include "hierarchy/hierarchy.h"
#include "mesh/roots.h"
#include "mesh/mesh.h"
#include "scene/camera.h"
#include "scene/rays.h"
#include "scene/scene.h"
#include "solve/hierarchical_view.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define INNER_TOLERANCE 1e-5 /* gathering rounds stop when no leaf changes by more (relative) */
/* After a step that refined more than LOOSE_SHARE of its links the next step will refine much of
 * what it solves: its rounds stop at LOOSE_TOLERANCE, and the step that refines nothing solves
 * to INNER_TOLERANCE before it stops. */
#define LOOSE_TOLERANCE 1e-4
#define LOOSE_SHARE 0.01
#define INNER_ROUNDS 1000
/* A step that refines no more than TAIL_SHARE of its links ends the solve once it has solved
 * them to INNER_TOLERANCE: every link passed the oracle at the radiosities it was refined with
 * (rad_hier_refine asks again of the links it makes), and a solve after refining a few tenths of
 * a percent of the links moves the radiosities too little to matter. Sponza (5.7 M links) now
 * stops after step 4, which refines 8,423 links (0.15%); steps 5-8 refined 306, 23, 4 and 0
 * for 17 more gathering rounds and four passes of the oracle, and its image is the same to the
 * digits block_compare.py prints but 8x8 RMSE 3.00% against 2.99% (docs/hierarchical.md, "Sponza,
 * fourth session"). */
#define TAIL_SHARE 2e-3

/* Light the nodes hold besides their materials' emission. Point, spot and directional lights
 * and the sky on each node itself (src/system/lights_direct.c, rad_node_lights_reflected:
 * exact point-to-node solid angles, Embree visibility from 16 points, sky rays from the node's
 * quarters), with how much it changes across the node, which makes the hierarchy split leaves
 * at shadow edges. Light through mirrors and glass (src/system/specular_first.c: the first
 * pass's deposit, and after a converged solve the second pass's) from the system's elements:
 * each polygon's elements are first[p] .. first[p + 1] in `element`, so a node takes the
 * deposit of the elements whose centroids it covers, area-weighted (the nearest element's when
 * it covers none). */
typedef struct element_light {
    const rad_system *system;
    size_t *first;
    uint32_t *element;
    rad_rgb *value;    /* per element: the lights' pre-pass and the deposits (evaluate()) */
    rad_rgb *specular; /* per element: the deposits alone; NULL without */
    rad_node_lights lights; /* rays NULL without lights or sky */
} element_light;

static void node_light(void *user, uint32_t polygon, const rad_vec3 *corners, int count,
                       uint64_t stream, double out[3], double *spread) {
    element_light *el = user;
    out[0] = out[1] = out[2] = 0;
    *spread = 0;
    if (el->lights.rays)
        rad_node_lights_reflected(&el->lights, polygon, corners, count, stream, out, spread);
    if (el->specular) {
        double deposit[3];
        rad_hier_elements_mean(el->system, el->specular, el->element, el->first[polygon],
                               el->first[polygon + 1], corners, count, deposit);
        for (int c = 0; c < 3; ++c) out[c] += deposit[c];
    }
}

static rad_status element_light_create(const rad_system *s, rad_rgb *reflection,
                                       element_light *out) {
    size_t polygons = s->geometry->polygon_count, n = s->element_count;
    int specular = s->specular_emission || reflection;
    out->system = s;
    out->first = rad_alloc_zero(s->ctx, polygons + 2, sizeof *out->first);
    out->element = rad_alloc(s->ctx, n ? n : 1, sizeof *out->element);
    out->value = rad_alloc_zero(s->ctx, n ? n : 1, sizeof *out->value);
    if (specular) out->specular = rad_alloc_zero(s->ctx, n ? n : 1, sizeof *out->specular);
    if (!out->first || !out->element || !out->value || (specular && !out->specular))
        return RAD_ERROR_NO_MEMORY;
    if (s->geometry->light_count || s->geometry->sky.kind != RAD_SKY_OFF) {
        out->lights.scene = s->geometry;
        rad_status status = rad_rays_create(s->ctx, s->geometry, &out->lights.rays);
        if (status) return status;
    }
    for (size_t e = 0; e < n; ++e) out->first[s->mesh->element_polygon[e] + 2]++;
    for (size_t p = 0; p < polygons; ++p) out->first[p + 2] += out->first[p + 1];
    for (size_t e = 0; e < n; ++e) out->element[out->first[s->mesh->element_polygon[e] + 1]++] = (uint32_t)e;
    rad_rgb *parts[3] = {s->light_emission, s->specular_emission, reflection};
    for (int k = 0; k < 3; ++k)
        for (size_t e = 0; parts[k] && e < n; ++e)
            for (int c = 0; c < 3; ++c) {
                out->value[e][c] += parts[k][e][c];
                if (k > 0) out->specular[e][c] += parts[k][e][c];
            }
    return RAD_OK;
}

static void element_light_destroy(const rad_system *s, element_light *el) {
    if (!el) return;
    rad_free(s->ctx, el->first);
    rad_free(s->ctx, el->element);
    rad_free(s->ctx, el->value);
    rad_free(s->ctx, el->specular);
    rad_rays_destroy(el->lights.rays);
    rad_free(s->ctx, el);
}

/* What a hierarchy was built with (hierarchical_view.h); the view owns it with the hierarchy,
 * since the nodes made later read their light through it. */
struct rad_hier_setup {
    double link_error; /* as used: --link-error, else the tolerance, else the default */
    int importance;
    element_light *light; /* NULL without lights, sky or specular light */
    int unfinished;       /* the last solve was cancelled (Ctrl-C): the next step finishes it */
    int loose;            /* the last solve was to LOOSE_TOLERANCE (a step that refined much) */
};

void rad_hier_setup_destroy(rad_system *s, rad_hier_setup *setup) {
    if (!setup) return;
    element_light_destroy(s, setup->light);
    rad_free(s->ctx, setup);
}

double rad_hier_setup_link_error(const rad_hier_setup *setup) { return setup->link_error; }
int rad_hier_setup_importance(const rad_hier_setup *setup) { return setup->importance; }
int rad_hier_setup_unfinished(const rad_hier_setup *setup) { return setup->unfinished; }
int rad_hier_setup_loose(const rad_hier_setup *setup) { return setup->loose; }
void rad_hier_setup_set_loose(rad_hier_setup *setup, int loose) { setup->loose = loose; }
void rad_hier_setup_set_unfinished(rad_hier_setup *setup, int unfinished) {
    setup->unfinished = unfinished;
}

/* Solves the hierarchy's links. Cancelled (Ctrl-C, through the progress callback), it keeps
 * the rounds done, a valid solution not yet converged, and marks it unfinished: the caller
 * stops at the end of its step and the solution so far can be saved; the next step (here or
 * after --resume) goes on with the same rounds before refining. */
static rad_status solve_links(rad_system *s, rad_hier *hier, rad_hier_setup *setup) {
    rad_status status =
        rad_hier_solve(hier, setup->loose ? LOOSE_TOLERANCE : INNER_TOLERANCE, INNER_ROUNDS);
    setup->unfinished = status == RAD_ERROR_CANCELLED;
    if (setup->unfinished) {
        rad_warn(s->ctx, "%s; the solution so far is kept", rad_context_error(s->ctx));
        status = RAD_OK;
    }
    return status;
}

/* The roots a one-element-per-root system was built from (rad_system_polygon_mesh: its
 * elements are rad_roots_create's roots, in order, with their corners and areas). */
static rad_status roots_of_mesh(const rad_system *s, rad_roots **out) {
    const rad_mesh *mesh = s->mesh;
    rad_roots *r = rad_alloc_zero(s->ctx, 1, sizeof *r);
    if (r) r->roots = rad_alloc_zero(s->ctx, mesh->element_count ? mesh->element_count : 1, sizeof *r->roots);
    if (!r || !r->roots) {
        rad_roots_destroy(s->ctx, r);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t e = 0; e < mesh->element_count; ++e) {
        rad_root *root = &r->roots[e];
        root->count = (uint32_t)rad_mesh_corner_count(mesh, e);
        for (uint32_t k = 0; k < root->count; ++k)
            root->corner[k] = mesh->vertices[mesh->element_vertices[e][k]];
        root->area = mesh->element_area[e];
        root->polygon = mesh->element_polygon[e];
    }
    r->count = mesh->element_count;
    *out = r;
    return RAD_OK;
}

rad_status rad_hier_setup_create(rad_system *s, double link_error, int importance,
                                 rad_rgb *reflection, rad_hier_setup **out, rad_hier **hier) {
    *out = NULL;
    *hier = NULL;
    rad_hier_setup *setup = rad_alloc_zero(s->ctx, 1, sizeof *setup);
    if (!setup) return RAD_ERROR_NO_MEMORY;
    setup->link_error = link_error;
    setup->importance = importance;
    if (!reflection) reflection = s->specular_reflection;
    rad_hier_options options = {0};
    options.link_error = link_error;
    /* Fine leaves of a small scene: links read their source's descendants by the receiver's
     * kernel (hierarchical_view.h). */
    if (link_error <= RAD_HIER_FINE_LINK_ERROR && !s->ff && s->mesh &&
        s->mesh->element_count <= RAD_HIER_GATHERED_ROOTS)
        options.source_depth = RAD_HIER_FINE_SOURCE_DEPTH;
    rad_status status = RAD_OK;
    if (s->light_emission || s->specular_emission || reflection) {
        /* Point, spot and directional lights, the sky and light through mirrors and glass:
         * their light, reflected, is each node's emission besides its material's
         * (docs/hierarchical.md). */
        setup->light = rad_alloc_zero(s->ctx, 1, sizeof *setup->light);
        status = setup->light ? element_light_create(s, reflection, setup->light) : RAD_ERROR_NO_MEMORY;
        options.light = node_light;
        options.light_user = setup->light;
        /* A caustic has edges of its own, which no link asks for: the nodes resolve it first. */
        options.light_split = s->specular_emission != NULL;
    }
    /* A one-element-per-root system (no form-factor provider) holds the roots already cut. */
    rad_roots *roots = NULL;
    if (!status && !s->ff && s->mesh) status = roots_of_mesh(s, &roots);
    if (!status) status = rad_hier_create_from(s->ctx, s->geometry, &options, roots, hier);
    rad_roots_destroy(s->ctx, roots);
    if (status) {
        rad_hier_setup_destroy(s, setup);
        return status;
    }
    *out = setup;
    return RAD_OK;
}

/* The solver's state: the hierarchy and what it was built with. */
typedef struct hierarchical_state {
    rad_hier *hier;
    rad_hier_setup *setup;
    int drawn; /* the system's view owns both (rad_hier_view_install) */
} hierarchical_state;

/* Each element's radiosity. When the elements are the hierarchy's roots (one per polygon, or
 * one per fan triangle: rad_mesh_options.polygons_only), a root's radiosity, which push-pull
 * made the area-weighted mean of its leaves; otherwise the mean over the element's centroid and
 * the points halfway to its corners; with lights, the element's own pre-pass light replaces the
 * leaves' (which may be coarser). */
static void evaluate(rad_system *s, const rad_hier *hier, const element_light *light) {
    rad_rgb *value = light ? light->value : NULL;
    const rad_mesh *mesh = s->mesh;
    size_t node_count;
    const rad_hier_node *nodes = rad_hier_nodes(hier, &node_count);
#pragma omp parallel for schedule(static) num_threads(rad_thread_count(s->ctx)) \
    if (s->element_count >= 1024)
    for (long e = 0; e < (long)s->element_count; ++e) {
        uint32_t polygon = mesh->element_polygon[e], root_count;
        const uint32_t *roots = rad_hier_polygon_roots(hier, polygon, &root_count);
        /* This element's place among its polygon's elements (they are consecutive). */
        size_t first = (size_t)e, last = (size_t)e + 1;
        while (first > 0 && mesh->element_polygon[first - 1] == polygon) --first;
        while (last < s->element_count && mesh->element_polygon[last] == polygon) ++last;
        if (roots && last - first == root_count &&
            fabs(nodes[roots[(size_t)e - first]].area - mesh->element_area[e]) <=
                1e-9 * mesh->element_area[e]) {
            memcpy(s->radiosity[e], nodes[roots[(size_t)e - first]].radiosity, sizeof(rad_rgb));
            memset(s->unshot[e], 0, sizeof(rad_rgb));
            continue;
        }
        rad_vec3 centre = mesh->element_centroid[e];
        int corners = rad_mesh_corner_count(mesh, (size_t)e);
        double sum[3], b[3];
        rad_hier_radiosity_at(hier, polygon, centre, sum);
        for (int k = 0; k < corners; ++k) {
            rad_vec3 corner = mesh->vertices[mesh->element_vertices[e][k]];
            rad_hier_radiosity_at(hier, polygon, v3_lerp(centre, corner, 0.5), b);
            for (int c = 0; c < 3; ++c) sum[c] += b[c];
        }
        if (value) {
            double light[3];
            rad_hier_light_at(hier, mesh->element_polygon[e], centre, light);
            for (int c = 0; c < 3; ++c) sum[c] += (corners + 1) * (value[e][c] - light[c]);
        }
        for (int c = 0; c < 3; ++c) {
            s->radiosity[e][c] = sum[c] / (corners + 1);
            s->unshot[e][c] = 0;
        }
    }
}

/* Importance (Smits, Arvo & Salesin 1992): the oracle weighs links by what the camera of the
 * solve options sees, at the size the importance solver uses. */
static rad_status set_view(rad_solver_run *run, rad_hier *hier) {
    const rad_solve_options *o = run->options;
    rad_context *ctx = run->system->ctx;
    if (!o->camera)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the hierarchical solver's importance needs a camera "
                        "(rad_solve_options.camera)");
    int width, height;
    rad_importance_view_size(o, &width, &height);
    rad_camera camera = rad_camera_from_desc(o->camera);
    rad_view view;
    rad_status status = rad_view_make(ctx, &camera, width, height, &view);
    if (!status) status = rad_hier_set_view(hier, &view);
    if (!status) {
        rad_hier_stats stats = rad_hier_get_stats(hier);
        rad_info(ctx, "hierarchical importance: the camera sees surfaces in %.1f%% of a %dx%d view",
                 100 * stats.seen_share, width, height);
        if (!(stats.seen_share > 0))
            rad_warn(ctx, "importance: the camera sees no surface; every link counts as unseen");
    }
    return status;
}

static rad_status hierarchical_begin(rad_solver_run *run) {
    rad_system *s = run->system;
    const rad_solve_options *o = run->options;
    if (!s->geometry || !s->mesh)
        return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the hierarchical solver needs geometry; a patch system (.ffm) has only "
                        "its given form factors");
    if (o->link_error < 0 || isnan(o->link_error))
        return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "the link error must be a positive number, not %g", o->link_error);
    double link_error = o->link_error > 0 ? o->link_error : o->tolerance;
    int importance = rad_run_option(run, "importance", 0) != 0;
    /* None given: a small scene drawn through a final gather is refined to fine leaves (the
     * system is one element per root when it has no form-factor provider). */
    if (!(link_error > 0) && !importance && rad_run_option(run, "final-gather", 0) > 0 && !s->ff &&
        s->mesh->element_count <= RAD_HIER_GATHERED_ROOTS)
        link_error = RAD_HIER_GATHERED_LINK_ERROR;
    if (!(link_error > 0)) link_error = RAD_HIER_DEFAULT_LINK_ERROR;
    hierarchical_state *state = rad_alloc_zero(s->ctx, 1, sizeof *state);
    if (!state) return RAD_ERROR_NO_MEMORY;
    run->state = state;
    run->own_measure = 1; /* converged by the oracle (refine_and_solve), not the tolerance */
    /* Going on from a saved hierarchy (rad_system_load_solution restored it as it was): the
     * next step refines and solves exactly as the run that saved it would have. */
    rad_hier_setup *saved = rad_hier_view_setup(s);
    if (o->resume && saved && rad_hier_view_take_restored(s)) {
        if (saved->link_error != link_error)
            return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT,
                            "the saved hierarchy was refined with link error %g; go on with the "
                            "same --link-error (not %g)", saved->link_error, link_error);
        if (saved->importance != importance)
            return rad_fail(s->ctx, RAD_ERROR_INVALID_ARGUMENT,
                            "the saved hierarchy was refined %s importance; go on %s --importance",
                            saved->importance ? "with" : "without",
                            saved->importance ? "with" : "without");
        state->hier = rad_hier_view_hierarchy(s);
        state->setup = saved;
        state->drawn = 1;
        evaluate(s, state->hier, saved->light);
        return RAD_OK;
    }
    /* The driver resumes after the second specular pass (D S+ D light added to the elements):
     * the hierarchy starts over with it. */
    if (o->resume && !s->specular_reflection)
        rad_warn(s->ctx, "the hierarchical solver starts over: the solution it resumes is not a "
                         "saved hierarchy");
    rad_hier *hier = NULL;
    rad_status status = rad_hier_setup_create(s, link_error, importance, NULL, &state->setup, &hier);
    state->hier = hier;
    if (!status && importance) status = set_view(run, hier);
    if (!status) status = rad_hier_link_roots(hier);
    if (!status) status = solve_links(s, hier, state->setup);
    if (status) return status; /* hierarchical_end frees the state */
    /* The outputs draw the leaves (hierarchical_view.c); the system owns the hierarchy now. */
    status = rad_hier_view_install(s, hier, state->setup, 0);
    if (status) return status;
    state->drawn = 1;
    evaluate(s, hier, state->setup->light);
    return RAD_OK;
}

void rad_hier_view_evaluate(rad_system *s) {
    rad_hier *hier = rad_hier_view_hierarchy(s);
    if (hier) evaluate(s, hier, rad_hier_view_setup(s)->light);
}

/* The step's line in the log: what the hierarchy holds and how far the oracle is from met. */
static void report_step(rad_system *s, const rad_hier *hier, int iteration) {
    rad_hier_stats stats = rad_hier_get_stats(hier);
    rad_info(s->ctx,
             "hierarchical step %d: %zu links (%zu to clusters), %zu leaves, %zu clusters, "
             "largest error found %.3g of the threshold, %zu refined, largest remaining error "
             "%.3g, %d gathering rounds",
             iteration, stats.links, stats.cluster_links, stats.leaves, stats.clusters,
             stats.found_error, stats.refined, stats.largest_error, stats.solve_rounds);
    if (stats.budget_reached)
        rad_info(s->ctx,
                 "hierarchical step %d: the memory budget leaves %zu links over the threshold "
                 "(%zu of them not yet estimated: their ends overlap)",
                 iteration, stats.unrefined, stats.unknown_error);
}

/* One refinement of the links and the solve after it. Cancelled (Ctrl-C) while refining, the
 * hierarchy keeps the refinement as far as it got (rad_hier_refining) and *stopped is set, as
 * it is when the solve is cancelled (setup->unfinished). */
static rad_status refine_and_solve(rad_solver_run *run, int iteration, double *residual,
                                   int *stopped) {
    hierarchical_state *state = run->state;
    rad_hier *hier = state->hier;
    rad_hier_setup *setup = state->setup;
    run->own_stop = RAD_STOP_CONVERGED; /* no tail rule yet */
    run->own_converged = 0;
    rad_status status = rad_hier_refine(hier);
    *stopped = status == RAD_ERROR_CANCELLED && rad_hier_refining(hier, NULL);
    if (*stopped) {
        rad_warn(run->system->ctx, "%s; the refinement so far is kept",
                 rad_context_error(run->system->ctx));
        *residual = INFINITY;
        return RAD_OK;
    }
    if (status) return status;
    rad_hier_stats stats = rad_hier_get_stats(hier);
    /* The residual is the oracle's error, in the units of the link error (a fraction of the
     * emitted power): the largest it found at the radiosities the step began with, the links
     * it refined included. At most the link error, the oracle is met: converged. */
    *residual = stats.found_error * setup->link_error;
    run->own_converged = stats.refined == 0 && !setup->loose;
    if (stats.refined > 0 || setup->loose) {
        /* Solve only as tight as the next refinement needs: loosely after a step that refined
         * much (the next will refine again), to INNER_TOLERANCE otherwise and at the end. */
        setup->loose = stats.refined > 0 && (double)stats.refined > LOOSE_SHARE * (double)stats.links;
        status = solve_links(run->system, hier, setup);
        /* Nothing refined after a loose solve: the tight solve may move a link over the
         * threshold, so one more step asks the oracle again (own_converged stays 0). */
        /* The tail rule: the solve ends here, converged by the tail rule's condition (every
         * link passed the oracle at the radiosities it was refined with, and the few refined
         * are solved), and the residual is that: the largest error left after the refinement,
         * at most the link error. Not when the solve was cancelled (Ctrl-C, the time budget):
         * that stop is reported. */
        if (stats.refined > 0 && !setup->loose && !setup->unfinished &&
            (double)stats.refined <= TAIL_SHARE * (double)stats.links) {
            run->own_stop = RAD_STOP_TAIL;
            run->own_converged = 1;
            *residual = stats.largest_error * setup->link_error;
        }
        if (setup->unfinished) run->own_converged = 0;
        if (!status) evaluate(run->system, hier, setup->light);
        *stopped = setup->unfinished;
    }
    if (!status && stats.budget_reached && stats.links <= 1) {
        /* Not even the top cluster's first links fit: the budget's message, which names them. */
        char budget[512];
        snprintf(budget, sizeof budget, "%s", rad_context_error(run->system->ctx));
        return rad_fail(run->system->ctx, RAD_ERROR_MEMORY_BUDGET,
                        "%s: not even the first links fit", budget);
    }
    if (!status) report_step(run->system, hier, iteration);
    if (!status) {
        run->links = stats.links;
        run->leaves = stats.leaves;
        run->largest_error = stats.largest_error;
    }
    if (!status && stats.budget_reached) {
        /* The oracle is not met: the best solution within the budget, not converged. The
         * residual is the largest error known among the links still over the threshold (the
         * log line above counts them). */
        run->own_stop = RAD_STOP_MEMORY_BUDGET;
        run->own_converged = 0;
        *residual = stats.largest_error * setup->link_error;
    }
    return status;
}

static rad_status hierarchical_step(rad_solver_run *run, int iteration, double *residual) {
    hierarchical_state *state = run->state;
    rad_hier *hier = state->hier;
    rad_hier_setup *setup = state->setup;
    rad_status status = RAD_OK;
    int stopped = 0;
    run->own_converged = 0;
    /* What the last step (or the run before a saved file) left when Ctrl-C stopped it is done
     * first: a solve is finished to the tolerance it was begun with, a refinement goes on and
     * is solved. Then this step's own refinement and solve, so that the steps are the ones of a
     * run never stopped. */
    if (setup->unfinished) {
        status = solve_links(run->system, hier, setup);
        if (!status) evaluate(run->system, hier, setup->light);
        stopped = setup->unfinished;
    } else if (rad_hier_refining(hier, NULL)) {
        status = refine_and_solve(run, iteration - 1, residual, &stopped); /* the last step's */
        if (!status && run->own_stop == RAD_STOP_MEMORY_BUDGET) return RAD_OK;
    }
    if (!status && stopped) {
        *residual = INFINITY;
        return RAD_OK;
    }
    if (!status) status = refine_and_solve(run, iteration, residual, &stopped);
    return status;
}

/* The hierarchy stays when the system's view draws its leaves. */
static void hierarchical_end(rad_solver_run *run) {
    hierarchical_state *state = run->state;
    if (!state) return;
    if (!state->drawn) {
        rad_hier_destroy(state->hier);
        rad_hier_setup_destroy(run->system, state->setup);
    }
    rad_free(run->system->ctx, state);
    run->state = NULL;
}

static const rad_method_option hierarchical_options[] = {
    {"link-error", "E  the oracle's threshold on a link's error, relative to the emitted power "
                   "(1e-3, or --tolerance; 5e-6 in a final-gathered render of at most 256 roots)"},
    {"importance", "refine links where the camera needs them: the oracle weighs each link by "
                   "the importance of its receiver (Smits, Arvo & Salesin 1992)"},
    {"final-gather", "N  the solution is drawn through a final gather of N rays (render sets it): "
                     "with no link error given, a scene of at most 256 roots is refined to 5e-6"},
};

static const rad_solver_variant hierarchical_variants[] = {{"hierarchical", 0, 0}};

const rad_solver_impl rad_solver_hierarchical = {
    {"hierarchical", "quadtrees over the input polygons and links refined by an oracle "
                     "(Hanrahan, Salzman & Aupperle 1991)",
     RAD_SOLVER_ITERATIVE | RAD_SOLVER_OWN_LEAVES, hierarchical_options, 3, hierarchical_variants, 1, 0},
    hierarchical_begin, hierarchical_step, hierarchical_end,
};
