/* plot.h - convergence charts as SVG (cli/plot.c): one or more series of (seconds, value) drawn
 * against a linear time axis and a logarithmic value axis, with a legend; and whole-file
 * writes for the CLI's text outputs (temporary file renamed into place). */
#ifndef RAD_CLI_PLOT_H
#define RAD_CLI_PLOT_H

#include <stddef.h>

typedef struct plot_series {
    char name[48];
    double *x, *y; /* seconds, value (> 0 to be drawn) */
    size_t count, capacity;
    int dashed;    /* drawn dashed */
    int colour;    /* index into the palette; series of one solver share it */
} plot_series;

/* Appends a point; returns nonzero when out of memory. */
int plot_series_add(plot_series *series, double x, double y);
void plot_series_free(plot_series *series);

typedef struct plot_chart {
    const char *title;
    const char *x_label, *y_label;
    double y_line; /* a dashed horizontal line at this value (0: none), e.g. the 1% target */
} plot_chart;

/* Writes the chart of `count` series to path (whole or not at all). Returns 0, or prints one
 * "radiosity: ..." line and returns 1. */
int plot_write_svg(const char *path, const plot_chart *chart, const plot_series *series,
                   size_t count);

/* Writes `size` bytes to path through a temporary file in the same directory renamed into
 * place. Returns 0, or prints one "radiosity: ..." line and returns 1. */
int cli_write_whole(const char *path, const char *data, size_t size);

/* Checks, before long work, that a file can be created beside `path` (and that `path`, if it
 * exists, is not a directory). Returns 0, or prints one "radiosity: ..." line and returns 1. */
int cli_check_writable(const char *path);

/* Checks that `dir` is a directory where files can be created. Same return. */
int cli_check_directory(const char *dir);

#endif
