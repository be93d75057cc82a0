/* image_options.h - the output image flags of the commands that make an image straight from a
 * scene (pathtrace, photonmap): -o, the size, and how the file is written (--exposure,
 * --tonemap, --half), with their checks, so the two commands take and refuse them alike. */
#ifndef RAD_CLI_IMAGE_OPTIONS_H
#define RAD_CLI_IMAGE_OPTIONS_H

#include "cli.h"

#define CLI_IMAGE_MAX_SIDE 16384

typedef struct cli_image_args {
    const char *output, *tonemap;
    int width, height, half;
    double exposure;
} cli_image_args;

/* Three groups of option-table entries, written where each belongs in --help order. */
#define CLI_IMAGE_OUTPUT_OPTIONS(args)                                                            \
    {"-o", CLI_STRING, &(args)->output, "FILE  output image: .png, .hdr, .pfm, .exr (required)"}, \
    {"--output", CLI_STRING, &(args)->output, "FILE  the same as -o"}
#define CLI_IMAGE_SIZE_OPTIONS(args)                                                              \
    {"--width", CLI_INT, &(args)->width, "W  image width in pixels (512)"},                        \
    {"--height", CLI_INT, &(args)->height, "H  image height in pixels (512)"}
#define CLI_IMAGE_FILE_OPTIONS(args)                                                              \
    {"--exposure", CLI_DOUBLE, &(args)->exposure, "EV  exposure in stops, PNG only (0)"},          \
    {"--tonemap", CLI_STRING, &(args)->tonemap,                                                   \
     "CURVE  none|clamp|reinhard|aces, PNG only (clamp)"},                                        \
    {"--half", CLI_FLAG, &(args)->half, "EXR only: 16-bit half floats (default 32-bit float)"}

/* 512 x 512, clamp, no output yet. */
void cli_image_args_init(cli_image_args *args);

/* Prints a usage error and returns EXIT_USAGE without an output or with a side outside
 * 1 .. CLI_IMAGE_MAX_SIDE; 0 otherwise. */
int cli_image_check(const char *command, const cli_image_args *args);

/* The save options, and whether the output can be written (extension, tone curve, place):
 * 0, or after one error line EXIT_USAGE (a bad extension or curve) or 1 (an unwritable place). */
int cli_image_check_path(rad_context *ctx, const cli_image_args *args, rad_image_save_options *save);

/* What pathtrace and photonmap hold while they draw: the context, how the image is saved, the
 * scene, and the status of the work so far (a failed load, then the drawing's). */
typedef struct cli_image_run {
    rad_context *ctx;
    rad_image_save_options save;
    rad_scene *scene;
    rad_status status;
} cli_image_run;

/* The two commands' set-up: the context (with progress), the output checked, the scene
 * `scene_name` loaded and the output checked against the scene's own files. Returns 0 with
 * `run` filled (its status the load's: the scene is NULL when that failed), or an exit status
 * after one error line, with nothing left to free. */
int cli_image_open(const char *command, const cli_image_args *args, int threads, uint64_t seed,
                   double max_memory_mib, int quiet, const char *scene_name, cli_image_run *run);

/* Saves `image` to the output when nothing has failed so far (run->status), in *seconds the
 * time it took, then clears the progress line. */
void cli_image_write(cli_image_run *run, const cli_image_args *args, const rad_image *image,
                     double *seconds);

/* Frees the scene and the context. */
void cli_image_close(cli_image_run *run);

#endif
