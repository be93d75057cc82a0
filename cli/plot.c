/* plot.c - convergence charts as SVG, and whole-file writes for the CLI (see plot.h).
 * The chart is hand-written SVG 1.1: axes with tick labels, one polyline per series thinned to
 * what the pixels can show, a legend on the right. */
#include "plot.h"

#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int plot_series_add(plot_series *s, double x, double y) {
    if (s->count == s->capacity) {
        size_t capacity = s->capacity ? 2 * s->capacity : 256;
        double *nx = realloc(s->x, capacity * sizeof *nx);
        if (!nx) return 1;
        s->x = nx;
        double *ny = realloc(s->y, capacity * sizeof *ny);
        if (!ny) return 1;
        s->y = ny;
        s->capacity = capacity;
    }
    s->x[s->count] = x;
    s->y[s->count] = y;
    s->count++;
    return 0;
}

void plot_series_free(plot_series *s) {
    free(s->x);
    free(s->y);
    s->x = s->y = NULL;
    s->count = s->capacity = 0;
}

/* ------------------------------------------------------------------------------------------- */
/* Whole-file writes.                                                                            */

/* The library's output rules (rad_output_write): symbolic links followed, regular files
 * replaced whole by rename, devices, FIFOs and sockets written through, never replaced. */
static int output_call(const char *path, const char *data, size_t size, int write) {
    rad_context *ctx = NULL;
    if (rad_context_create(NULL, &ctx)) return cli_error(1, "%s: out of memory", path);
    rad_status status = write ? rad_output_write(ctx, path, data, size) : rad_output_check(ctx, path);
    int result = status ? cli_error(1, "%s", rad_context_error(ctx)) : 0;
    rad_context_destroy(ctx);
    return result;
}

int cli_write_whole(const char *path, const char *data, size_t size) {
    return output_call(path, data, size, 1);
}

int cli_check_writable(const char *path) { return output_call(path, NULL, 0, 0); }

/* Creates and removes a file named `pattern` (with "%s" for `name` and ending in XXXXXX):
 * 0 when that works, else the error `failure` ("%s: <failure>: <reason>") is printed. */
static int probe_write(const char *name, const char *pattern, const char *failure) {
    size_t size = strlen(name) + strlen(pattern) + 1;
    char *probe = malloc(size);
    if (!probe) return cli_error(1, "%s: out of memory", name);
    snprintf(probe, size, pattern, name);
    int fd = mkstemp(probe);
    int saved = errno;
    if (fd >= 0) {
        close(fd);
        unlink(probe);
    }
    free(probe);
    return fd < 0 ? cli_error(1, "%s: %s: %s", name, failure, strerror(saved)) : 0;
}

int cli_check_directory(const char *dir) {
    struct stat st;
    if (stat(dir, &st) != 0) return cli_error(1, "%s: cannot use as a directory: %s", dir, strerror(errno));
    if (!S_ISDIR(st.st_mode)) return cli_error(1, "%s: is not a directory", dir);
    return probe_write(dir, "%s/.radiosity-probe-XXXXXX", "cannot write into the directory");
}

/* ------------------------------------------------------------------------------------------- */
/* The chart.                                                                                    */

#define WIDTH 760.0
#define HEIGHT 440.0
#define LEFT 72.0
#define RIGHT 190.0
#define TOP 40.0
#define BOTTOM 52.0

static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                      "#9467bd", "#8c564b", "#e377c2", "#17becf"};

/* A step of 1, 2 or 5 times a power of ten giving about `ticks` intervals over `range`. */
static double nice_step(double range, int ticks) {
    double raw = range / ticks, power = pow(10, floor(log10(raw)));
    double m = raw / power;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * power;
}

static void xml_text(FILE *out, const char *text) {
    for (const char *c = text; *c; ++c) {
        if (*c == '<') fputs("&lt;", out);
        else if (*c == '>') fputs("&gt;", out);
        else if (*c == '&') fputs("&amp;", out);
        else fputc(*c, out);
    }
}

int plot_write_svg(const char *path, const plot_chart *chart, const plot_series *series,
                   size_t count) {
    /* Ranges: time from 0, values over whole decades. */
    double x_max = 0, y_min = INFINITY, y_max = 0;
    for (size_t k = 0; k < count; ++k)
        for (size_t i = 0; i < series[k].count; ++i) {
            if (!(series[k].y[i] > 0) || !isfinite(series[k].y[i])) continue;
            x_max = fmax(x_max, series[k].x[i]);
            y_min = fmin(y_min, series[k].y[i]);
            y_max = fmax(y_max, series[k].y[i]);
        }
    if (!(y_max > 0)) y_min = 1e-6, y_max = 1;
    if (chart->y_line > 0) y_min = fmin(y_min, chart->y_line), y_max = fmax(y_max, chart->y_line);
    if (!(x_max > 0)) x_max = 1;
    double d_lo = floor(log10(y_min)), d_hi = ceil(log10(y_max));
    if (d_hi <= d_lo) d_hi = d_lo + 1;
    double x_step = nice_step(x_max, 6);
    x_max = ceil(x_max / x_step - 1e-9) * x_step;
    double pw = WIDTH - LEFT - RIGHT, ph = HEIGHT - TOP - BOTTOM;
#define PX(x) (LEFT + (x) / x_max * pw)
#define PY(y) (TOP + (d_hi - log10(y)) / (d_hi - d_lo) * ph)

    char *buffer = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&buffer, &size);
    if (!out) return cli_error(1, "%s: out of memory", path);
    fprintf(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                 "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
                 "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"12\">\n"
                 "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            WIDTH, HEIGHT, WIDTH, HEIGHT);
    if (chart->title) {
        fprintf(out, "<text x=\"%.1f\" y=\"24\" font-size=\"15\" text-anchor=\"middle\">",
                LEFT + pw / 2);
        xml_text(out, chart->title);
        fputs("</text>\n", out);
    }
    /* Grid and ticks: decades on y, nice steps on x. */
    fputs("<g stroke=\"#dddddd\" stroke-width=\"1\">\n", out);
    for (double d = d_lo; d <= d_hi + 1e-9; d += 1)
        fprintf(out, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", LEFT, PY(pow(10, d)),
                LEFT + pw, PY(pow(10, d)));
    for (double x = 0; x <= x_max + 1e-9 * x_max; x += x_step)
        fprintf(out, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", PX(x), TOP, PX(x),
                TOP + ph);
    fputs("</g>\n<g text-anchor=\"end\">\n", out);
    for (double d = d_lo; d <= d_hi + 1e-9; d += 1)
        fprintf(out, "<text x=\"%.1f\" y=\"%.1f\">1e%+d</text>\n", LEFT - 6, PY(pow(10, d)) + 4,
                (int)d);
    fputs("</g>\n<g text-anchor=\"middle\">\n", out);
    for (double x = 0; x <= x_max + 1e-9 * x_max; x += x_step)
        fprintf(out, "<text x=\"%.1f\" y=\"%.1f\">%g</text>\n", PX(x), TOP + ph + 16, x);
    fputs("</g>\n", out);
    fprintf(out, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
                 "stroke=\"black\"/>\n", LEFT, TOP, pw, ph);
    if (chart->x_label) {
        fprintf(out, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">", LEFT + pw / 2,
                HEIGHT - 12);
        xml_text(out, chart->x_label);
        fputs("</text>\n", out);
    }
    if (chart->y_label) {
        fprintf(out, "<text transform=\"translate(16 %.1f) rotate(-90)\" text-anchor=\"middle\">",
                TOP + ph / 2);
        xml_text(out, chart->y_label);
        fputs("</text>\n", out);
    }
    if (chart->y_line > 0)
        fprintf(out, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#555555\" "
                     "stroke-dasharray=\"5 4\"/>\n", LEFT, PY(chart->y_line), LEFT + pw,
                PY(chart->y_line));

    /* Series, thinned: a point is kept when it moves half a pixel from the last one kept. */
    for (size_t k = 0; k < count; ++k) {
        const char *colour = colours[(size_t)series[k].colour % (sizeof colours / sizeof colours[0])];
        fprintf(out, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.8\"%s points=\"",
                colour, series[k].dashed ? " stroke-dasharray=\"6 3\"" : "");
        double last_x = -1e9, last_y = -1e9;
        for (size_t i = 0; i < series[k].count; ++i) {
            double y = series[k].y[i];
            if (!(y > 0) || !isfinite(y)) continue;
            double px = PX(series[k].x[i]), py = PY(y);
            int final = i + 1 == series[k].count;
            if (!final && fabs(px - last_x) < 0.5 && fabs(py - last_y) < 0.5) continue;
            fprintf(out, "%.1f,%.1f ", px, py);
            last_x = px;
            last_y = py;
        }
        fputs("\"/>\n", out);
        double ly = TOP + 14 + 20.0 * (double)k;
        fprintf(out, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
                     "stroke-width=\"3\"%s/>\n", LEFT + pw + 14, ly - 4, LEFT + pw + 38, ly - 4,
                colour, series[k].dashed ? " stroke-dasharray=\"6 3\"" : "");
        fprintf(out, "<text x=\"%.1f\" y=\"%.1f\">", LEFT + pw + 44, ly);
        xml_text(out, series[k].name);
        fputs("</text>\n", out);
    }
    fputs("</svg>\n", out);
#undef PX
#undef PY
    if (fclose(out) != 0) {
        free(buffer);
        return cli_error(1, "%s: out of memory", path);
    }
    int status = cli_write_whole(path, buffer, size);
    free(buffer);
    return status;
}
