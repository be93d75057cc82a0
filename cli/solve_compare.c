/* solve_compare.c - `radiosity solve SCENE --compare-solvers [--plot FILE.svg]`: every solver
 * on the same system, one chart and one table.
 *
 * The solvers' own stopping measures differ (largest change for gathering, unshot power for
 * shooting), so the comparison uses one error for all, measured against a converged reference
 * solution B* computed first (Gauss-Seidel to 1e-10, or shooting to 1e-10 when the matrix does
 * not fit the memory budget):
 *
 *     error = sum_e A_e |B_e - B*_e| / sum_e A_e |B*_e|     (summed over channels)
 *
 * the fraction of the scene's power that is still wrong, and, when a camera sees the scene,
 * the view error, the same with each element weighted by its share of the image instead of its
 * area: the mean error of the picture. Every solver runs on a fresh system (same scene, mesh
 * and form-factor options), so each pays for the form factors it asks for, as it would alone:
 * times are the solvers' own, form factors included, the error measurement excluded.
 * A solver that refines its own leaves (the hierarchy) converges to another discretisation than
 * the elements': it is measured against its own converged solution (a first, untimed run to
 * the end), and a line under its row says how far that lies from the elements' reference.
 * docs/solvers.md, "Comparing the solvers". */
#include "cli.h"
#include "interrupt.h"
#include "solve_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TARGET 0.01        /* the table's "time to 1%" */
#define STOP_ERROR 1e-4    /* each run stops at this error */

typedef struct compare_run {
    char label[48];
    rad_solver_kind kind;
    double omega;
    int overshoot;
} compare_run;

static void print_reached(double seconds, long steps, rad_solver_kind kind) {
    if (seconds < 0) printf("  %-22s", "not reached");
    else {
        char text[48];
        snprintf(text, sizeof text, "%ld %s, %.3g s", steps, cli_step_word(kind, steps), seconds);
        printf("  %-22s", text);
    }
}

int solve_compare(rad_context *ctx, const rad_scene *scene, const rad_mesh_options *mesh_options,
                  const rad_ff_options *ff, const solve_args *a, const rad_camera_desc *camera) {
    /* Every solver runs on the same element mesh (one that draws its own leaves too). */
    rad_mesh_options shared_mesh = *mesh_options;
    shared_mesh.polygons_only = 0;
    const rad_mesh_options *mesh = &shared_mesh;
    rad_system *system = NULL;
    rad_status status = rad_system_create(ctx, scene, mesh, ff, &system);
    if (status) return cli_fail(ctx, status);
    size_t n = rad_system_element_count(system);
    double *reference = malloc(3 * n * sizeof *reference);
    double *share = malloc(n * sizeof *share);
    double *own_reference = malloc(3 * n * sizeof *own_reference);
    plot_series series[16];
    memset(series, 0, sizeof series);
    char *log_buffer = NULL;
    size_t log_size = 0;
    FILE *log = NULL;
    int exit_status = 0;
    if (!reference || !share || !own_reference) {
        exit_status = cli_error(1, "out of memory");
        goto done;
    }
    if (!a->pipe.quiet) fprintf(stderr, "radiosity: computing the reference solution\n");
    rad_solver_kind used;
    double tolerance;
    status = rad_system_solve_reference(system, reference, &used, &tolerance);
    if (status) {
        exit_status = cli_fail(ctx, status);
        goto done;
    }
    char how[64];
    snprintf(how, sizeof how, "%s to %g", rad_solver_kind_name(used), tolerance);
    /* What the camera sees; patch systems have no geometry and no view. */
    int have_view = 1;
    status = rad_system_screen_share(system, camera, a->width, a->height, share);
    if (status) {
        have_view = 0;
        if (!a->pipe.quiet) {
            char names[200];
            cli_solver_filter viewers = {RAD_SOLVER_NEEDS_CAMERA, 0, NULL};
            fprintf(stderr, "radiosity: no view error and no %s solver: %s\n",
                    cli_solver_names(names, sizeof names, &viewers, ", ", " or "),
                    rad_context_error(ctx));
        }
    } else if (isnan(rad_system_solution_error(system, reference, share))) {
        have_view = 0; /* the camera sees no light: no view error */
    }

    /* The runs: every registered solver's comparison variants (rad_solver_info.variants);
     * those that need a camera only when there is a view. */
    compare_run runs[8];
    int count = 0, series_count = 0;
    for (size_t i = 0; i < rad_solver_count(); ++i) {
        const rad_solver_info *info = rad_solver_at(i);
        if ((info->capabilities & RAD_SOLVER_NEEDS_CAMERA) && !have_view) continue;
        /* A solver of its own leaves needs geometry, which a scene without a view lacks. */
        if ((info->capabilities & RAD_SOLVER_OWN_LEAVES) && !have_view) continue;
        for (size_t v = 0; v < info->variant_count && count < 8; ++v) {
            const rad_solver_variant *variant = &info->variants[v];
            double omega = !variant->relaxed ? 1 : a->pipe.omega > 0 ? a->pipe.omega : info->best_omega;
            compare_run *run = &runs[count++];
            *run = (compare_run){"", (rad_solver_kind)(i + 1), omega, variant->overshoot};
            snprintf(run->label, sizeof run->label, variant->label, omega);
        }
    }

    if (a->log) {
        log = open_memstream(&log_buffer, &log_size);
        if (!log) {
            exit_status = cli_error(1, "out of memory");
            goto done;
        }
        fputs("solver,iteration,seconds,shots,sweeps,unshot_fraction,residual,error,view_error\n", log);
    }
    size_t patches = rad_system_patch_count(system);
    printf("solver comparison: %zu elements in %zu patches; error = sum A |B - B*| / sum A B* "
           "against %s%s\n", n, patches, how,
           have_view ? "; view error weights by share of the image" : "");
    printf("%-18s  %-22s  %-22s  %10s  %10s\n", "solver", "to 1% error", "to 1% view error",
           "end error", "seconds");
    for (int k = 0; k < count; ++k) {
        const compare_run *run = &runs[k];
        /* A fresh system: no form factors computed yet. */
        rad_system_destroy(system);
        system = NULL;
        status = rad_system_create(ctx, scene, mesh, ff, &system);
        if (status) {
            exit_status = cli_fail(ctx, status);
            goto done;
        }
        int shooting = cli_solver_shoots(run->kind);
        /* The error, and for the shooting solvers the view error dashed in the same colour
         * (for gathering the two fall together). */
        plot_series *line = &series[series_count++], *view_line = NULL;
        snprintf(line->name, sizeof line->name, "%.40s", run->label);
        line->colour = k;
        if (shooting && have_view) {
            view_line = &series[series_count++];
            snprintf(view_line->name, sizeof view_line->name, "%.36s, view", run->label);
            view_line->colour = k;
            view_line->dashed = 1;
        }
        solve_watch watch = {0};
        watch.system = system;
        watch.solver_name = run->label;
        watch.shooting = shooting;
        watch.tolerance = STOP_ERROR;
        watch.time_budget = isnan(a->time_budget) ? 0 : a->time_budget;
        watch.log = log;
        watch.log_prefix = run->label;
        watch.series = line;
        watch.view_series = view_line;
        watch.reference = reference;
        watch.view_share = have_view ? share : NULL;
        watch.stop_error = STOP_ERROR;
        watch.target = TARGET;
        watch.error_seconds = watch.view_error_seconds = -1;
        watch.progress = !a->pipe.quiet && isatty(STDERR_FILENO);

        rad_solve_options options = {0};
        options.solver = run->kind;
        options.omega = run->omega;
        rad_options own = {0};
        cli_solver_option(&own, options.solver, "overshoot", run->overshoot);
        /* The hierarchy's oracle would otherwise take the tolerance below as its link error:
         * --link-error, or the solver's default 1e-3 (docs/hierarchical.md). */
        double link_error = 0;
        cli_pipeline_link_error("solve", &a->pipe, &link_error); /* checked before */
        cli_solver_option(&own, options.solver, "link-error", link_error > 0 ? link_error : 1e-3);
        options.method_options = &own;
        options.tolerance = 1e-13; /* the error decides when to stop */
        options.max_iterations = a->pipe.iterations;
        options.time_budget = watch.time_budget;
        options.camera = camera;
        options.view_width = a->width;
        options.view_height = a->height;
        rad_solve_report report;
        int own_leaves = (rad_solver_get(run->kind)->capabilities & RAD_SOLVER_OWN_LEAVES) != 0;
        double own_difference = NAN;
        if (own_leaves) {
            /* Its own converged solution first (untimed, on a system of its own): what its
             * error falls to, and how far that lies from the elements' reference. */
            rad_system *first = NULL;
            rad_solve_options to_the_end = options;
            to_the_end.max_iterations = 0;
            to_the_end.time_budget = 0;
            status = rad_system_create(ctx, scene, mesh, ff, &first);
            if (!status) status = rad_solve(first, &to_the_end, &report);
            for (size_t e = 0; !status && e < n; ++e)
                status = rad_system_element_radiosity(first, e, &own_reference[3 * e]);
            if (!status) own_difference = rad_system_solution_error(first, reference, NULL);
            rad_system_destroy(first);
            if (status) {
                exit_status = cli_fail(ctx, status);
                goto done;
            }
            watch.reference = own_reference;
        }
        options.on_iteration = solve_watch_iteration;
        options.iteration_user = &watch;
        status = rad_solve(system, &options, &report);
        solve_watch_finish(&watch);
        if (status) {
            exit_status = cli_fail(ctx, status);
            goto done;
        }
        if (watch.failed) {
            exit_status = 1;
            goto done;
        }
        solve_watch_measure(&watch);
        printf("%-18s", run->label);
        print_reached(watch.error_seconds, watch.error_steps, run->kind);
        if (have_view) print_reached(watch.view_error_seconds, watch.view_error_steps, run->kind);
        else printf("  %-22s", "-");
        printf("  %10.3g  %10.3g\n", watch.last_error, report.seconds);
        if (own_leaves)
            printf("  (%s: against its own converged solution, %zu leaves at link error %g; that "
                   "lies %.3g from the reference above: a different mesh, not convergence)\n",
                   run->label, report.leaves, link_error > 0 ? link_error : 1e-3, own_difference);
        fflush(stdout);
        if (cli_interrupted()) {
            exit_status = cli_interrupt_exit_status();
            break;
        }
    }
    if (log) {
        fclose(log);
        log = NULL;
        if (cli_write_whole(a->log, log_buffer, log_size)) {
            exit_status = 1;
            goto done;
        }
    }
    if (a->plot) {
        char title[160];
        snprintf(title, sizeof title, "%s: %zu elements, error against a converged solution",
                 a->scene_name ? a->scene_name : "convergence", n);
        plot_chart chart = {title, "seconds", "error (dashed: view error)", TARGET};
        exit_status = plot_write_svg(a->plot, &chart, series, (size_t)series_count);
    }
done:
    if (log) fclose(log);
    free(log_buffer);
    for (int k = 0; k < 16; ++k) plot_series_free(&series[k]);
    free(reference);
    free(share);
    free(own_reference);
    rad_system_destroy(system);
    return exit_status;
}
