/* solve_watch.c - the iteration callback of `radiosity solve` (see solve_watch.h). */
#include "solve_watch.h"

#include "cli.h"
#include "interrupt.h"
#include "progress.h"

#include <math.h>
#include <string.h>

void solve_watch_measure(solve_watch *w) {
    w->last_error = rad_system_solution_error(w->system, w->reference, NULL);
    w->last_view_error =
        w->view_share ? rad_system_solution_error(w->system, w->reference, w->view_share) : NAN;
}

/* Time left from the residual's recent rate of decay: ln(r / tolerance) / rate, where the rate
 * is measured over the last fifth of the run (at least the last second). */
static double time_left(solve_watch *w, double seconds, double residual) {
    if (!(residual > 0)) return 0;
    double lr = log(residual);
    if (w->history_count == 0 || seconds - w->history_t[(w->history_count - 1) % 64] >= 0.25) {
        w->history_t[w->history_count % 64] = seconds;
        w->history_r[w->history_count % 64] = lr;
        w->history_count++;
    }
    double window = fmax(1.0, 0.2 * seconds);
    int oldest = w->history_count > 64 ? w->history_count - 64 : 0;
    for (int i = oldest; i < w->history_count; ++i) {
        double dt = seconds - w->history_t[i % 64];
        if (dt <= window && dt > 0.2) {
            double rate = (w->history_r[i % 64] - lr) / dt;
            if (rate > 0) return log(residual / w->tolerance) / rate;
            return NAN;
        }
    }
    return NAN;
}

static void draw_progress(solve_watch *w, const rad_iteration_event *event) {
    double now = cli_seconds();
    double left = time_left(w, event->seconds, event->residual);
    if (now - w->last_draw < 0.1) return;
    if (w->last_draw == 0) cli_progress_clear(); /* the bar of the phases before */
    w->last_draw = now;
    char eta[48] = "";
    if (w->time_budget > 0) {
        double budget_left = fmax(0, w->time_budget - event->seconds);
        if (!isfinite(left) || left > budget_left) left = budget_left;
    }
    if (isfinite(left)) snprintf(eta, sizeof eta, ", about %.0f s left", ceil(fmax(0, left)));
    if (w->shooting)
        fprintf(stderr, "\r\033[K%s: %ld shots, unshot power %.3g%% of emitted%s", w->solver_name,
                event->shots + w->step_offset, 100 * event->unshot_fraction, eta);
    else if (event->links)
        fprintf(stderr, "\r\033[K%s: step %ld, %zu links, %zu leaves, oracle's error %.3g "
                        "(largest left %.3g of the threshold)%s", w->solver_name,
                event->rounds + w->step_offset, event->links, event->leaves, event->residual,
                event->largest_error, eta);
    else
        fprintf(stderr, "\r\033[K%s: round %ld, change %.3g%s", w->solver_name,
                event->rounds + w->step_offset, event->residual, eta);
    fflush(stderr);
}

void solve_watch_finish(solve_watch *w) {
    if (w->progress && w->last_draw > 0) {
        fputs("\r\033[K", stderr);
        fflush(stderr);
    }
}

static void log_number(FILE *out, double value) {
    if (isfinite(value)) fprintf(out, "%.9g", value);
}

int solve_watch_iteration(void *user, const rad_iteration_event *event) {
    solve_watch *w = user;
    long step = (long)event->iteration + w->step_offset;
    if (w->reference) {
        solve_watch_measure(w);
        if (w->error_seconds < 0 && w->last_error <= w->target) {
            w->error_seconds = event->seconds;
            w->error_steps = step;
        }
        if (w->view_error_seconds < 0 && w->last_view_error <= w->target) {
            w->view_error_seconds = event->seconds;
            w->view_error_steps = step;
        }
    }
    if (w->log) {
        if (w->log_prefix)
            fprintf(w->log, strchr(w->log_prefix, ',') ? "\"%s\"," : "%s,", w->log_prefix);
        fprintf(w->log, "%ld,%.6f,%ld,%ld,", step, event->seconds,
                w->shooting ? event->shots + w->step_offset : 0,
                w->shooting ? 0 : event->rounds + w->step_offset);
        log_number(w->log, event->unshot_fraction);
        fputc(',', w->log);
        log_number(w->log, event->residual);
        if (w->reference) {
            fputc(',', w->log);
            log_number(w->log, w->last_error);
            fputc(',', w->log);
            log_number(w->log, w->last_view_error);
        }
        if (w->hierarchy) {
            fprintf(w->log, ",%zu,%zu,", event->links, event->leaves);
            log_number(w->log, event->largest_error);
        }
        fputc('\n', w->log);
    }
    if (w->series) {
        double value = w->reference ? w->last_error : event->residual;
        if (plot_series_add(w->series, event->seconds, value) ||
            (w->view_series &&
             plot_series_add(w->view_series, event->seconds, w->last_view_error))) {
            w->failed = cli_error(1, "out of memory for the plot");
            return 1;
        }
    }
    if (w->progress) draw_progress(w, event);
    if (w->snapshot && w->snapshot_every > 0 && step % w->snapshot_every == 0 &&
        w->snapshot(w->snapshot_user, step)) {
        w->failed = 1;
        return 1;
    }
    if (w->reference && w->stop_error > 0 && w->last_error <= w->stop_error) return 1;
    return cli_interrupted();
}
