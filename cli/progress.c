/* progress.c - the progress bar on stderr (see progress.h).
 *
 *   rendering     [##########..........]  48%  246/512  812/s  0.3 s left
 *
 * Drawn at most ten times a second, only when stderr is a terminal; the line is rewritten in
 * place (carriage return, then erase to the end of the line). Solver phases report a safety cap
 * as their total, not a forecast, so they show the count and the rate without a bar.
 *
 * When stderr is not a terminal the same line is printed whole, with "radiosity: [PHASE]" in
 * front and a newline, every BATCH_SECONDS of one phase (none for work that ends sooner), and
 * cli_stage prints one line per stage. */
#include "progress.h"

#include "cli.h"
#include "interrupt.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BAR_WIDTH 24
#define REDRAW_SECONDS 0.1
#define BATCH_SECONDS 5.0

static struct {
    int enabled;   /* stderr is a terminal and not --quiet */
    int batch;     /* stderr is not a terminal and not --quiet: stage and progress lines */
    int quiet;
    int shown;     /* a bar is on the line now */
    char phase[48];
    double phase_start, phase_start_done, last_draw;
} bar;

void cli_progress_clear(void) {
    if (!bar.shown) return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    bar.shown = 0;
}

/* Phases whose total is a cap rather than the amount of work. */
static int open_ended(const char *phase) {
    for (int k = 0; k < 16; ++k) {
        const char *name = rad_solver_kind_name((rad_solver_kind)k);
        if (name && strcmp(name, phase) == 0) return 1;
    }
    return 0;
}

static void format_rate(char *out, size_t size, double rate) {
    if (rate >= 100) snprintf(out, size, "%.0f/s", rate);
    else snprintf(out, size, "%.3g/s", rate);
}

static void format_duration(char *out, size_t size, double seconds) {
    if (seconds < 60) snprintf(out, size, "%.1f s", seconds);
    else if (seconds < 3600) snprintf(out, size, "%d min %02d s", (int)(seconds / 60), (int)seconds % 60);
    else if (seconds < 86400) snprintf(out, size, "%d h %02d min", (int)(seconds / 3600), (int)(seconds / 60) % 60);
    else snprintf(out, size, "%.0f days", seconds / 86400);
}

int cli_progress_report(void *user, const char *phase, double done, double total) {
    (void)user;
    if (cli_interrupted()) return 1; /* Ctrl-C: the library stops and reports it cancelled */
    if (!(bar.enabled || bar.batch) || !phase) return 0;
    double now = cli_seconds();
    if (strncmp(bar.phase, phase, sizeof bar.phase - 1) != 0) {
        snprintf(bar.phase, sizeof bar.phase, "%s", phase);
        bar.phase_start = now;
        bar.phase_start_done = done;
        bar.last_draw = bar.batch ? now : 0;
    }
    int finished = total > 0 && done >= total;
    if (bar.batch ? now - bar.last_draw < BATCH_SECONDS || finished
                  : now - bar.last_draw < REDRAW_SECONDS && !finished)
        return 0;
    bar.last_draw = now;
    double elapsed = now - bar.phase_start;
    double rate = elapsed > 0 ? (done - bar.phase_start_done) / elapsed : 0;
    /* The counts after the phase (and the bar): "48%  246/512  812/s  0.3 s left". */
    char counts[128], cells[BAR_WIDTH + 1] = "";
    int n;
    if (open_ended(phase) || !(total > 0)) {
        n = snprintf(counts, sizeof counts, "%.0f", done);
        char speed[32];
        format_rate(speed, sizeof speed, rate);
        if (rate > 0) n += snprintf(counts + n, sizeof counts - (size_t)n, "  %s", speed);
    } else {
        double fraction = done / total < 1 ? done / total : 1;
        int filled = (int)(fraction * BAR_WIDTH);
        for (int i = 0; i < BAR_WIDTH; ++i) cells[i] = i < filled ? '#' : '.';
        cells[BAR_WIDTH] = '\0';
        n = snprintf(counts, sizeof counts, "%3.0f%%  %.0f/%.0f", 100 * fraction, done, total);
        if (rate > 0) {
            char left[32], speed[32];
            format_duration(left, sizeof left, (total - done) / rate);
            format_rate(speed, sizeof speed, rate);
            n += snprintf(counts + n, sizeof counts - (size_t)n, "  %s  %s left", speed, left);
        }
    }
    (void)n;
    if (bar.batch) {
        char took[32];
        format_duration(took, sizeof took, elapsed);
        fprintf(stderr, "radiosity: [%s] %s  (%s so far)\n", phase, counts, took);
        fflush(stderr);
        return 0;
    }
    char line[200];
    if (cells[0]) snprintf(line, sizeof line, "%-13s [%s] %s", phase, cells, counts);
    else snprintf(line, sizeof line, "%-13s %s", phase, counts);
    fprintf(stderr, "\r%s\033[K", line);
    fflush(stderr);
    bar.shown = 1;
    return 0;
}

static void log_line(void *user, rad_log_level level, const char *message) {
    (void)user;
    if (bar.quiet && level != RAD_LOG_WARNING) return;
    cli_progress_clear();
    fprintf(stderr, "radiosity: %s%s\n", level == RAD_LOG_WARNING ? "warning: " : "", message);
}

rad_context *cli_context_with_progress(int threads, uint64_t seed, double max_memory_mib,
                                       int quiet) {
    cli_interrupt_install();
    bar.quiet = quiet;
    bar.enabled = !quiet && isatty(STDERR_FILENO);
    bar.batch = !quiet && !bar.enabled;
    rad_context_options options = {0};
    options.log = log_line;
    options.progress = cli_progress_report;
    options.threads = threads;
    options.seed = seed;
    options.max_memory = max_memory_mib > 0 ? (uint64_t)(max_memory_mib * 1048576.0) : 0;
    rad_context *ctx = NULL;
    rad_status status = rad_context_create(&options, &ctx);
    if (status) {
        cli_error(1, "cannot create a context: %s", rad_status_name(status));
        exit(1);
    }
    return ctx;
}

void cli_stage(const char *stage, const char *format, ...) {
    if (!bar.batch) return;
    fprintf(stderr, "radiosity: [%s] ", stage);
    va_list args;
    va_start(args, format);
    vfprintf(stderr, format, args);
    va_end(args);
    fputc('\n', stderr);
    fflush(stderr);
}

void cli_stage_mesh(const rad_system *system, double seconds) {
    cli_stage("mesh", "%zu surfaces, %zu patches, %zu elements, %.2f s",
              rad_system_surface_count(system), rad_system_patch_count(system),
              rad_system_element_count(system), seconds);
}

const char *cli_solve_outcome(const rad_solve_report *report) {
    if (!report->converged) return "not converged";
    return report->stop == RAD_STOP_TAIL ? "converged (tail rule)" : "converged";
}

const char *cli_residual_text(char *out, size_t size, const rad_solve_report *report) {
    /* Infinite when a step was cut short (Ctrl-C, the time budget) before its measure was
     * taken: the hierarchy's oracle has then not been asked at the radiosities solved. */
    if (!isfinite(report->residual)) snprintf(out, size, "not measured");
    else snprintf(out, size, "%.3g", report->residual);
    return out;
}

void cli_stage_solve(const rad_solve_options *solve, const rad_solve_report *report) {
    char hierarchy[96] = "", residual[32];
    if (report->links) /* the hierarchical solver's links and leaves */
        snprintf(hierarchy, sizeof hierarchy, ", %zu links, %zu leaves", report->links,
                 report->leaves);
    cli_stage("solve", "%s, %d %s, residual %s, %s%s, %.2f s", rad_solver_kind_name(solve->solver),
              report->iterations, cli_step_word(solve->solver, report->iterations),
              cli_residual_text(residual, sizeof residual, report), cli_solve_outcome(report),
              hierarchy, report->seconds);
}
