/* image_options.c - the output image flags shared by pathtrace and photonmap (image_options.h). */
#include "image_options.h"
#include "output_path.h"
#include "progress.h"

void cli_image_args_init(cli_image_args *args) {
    args->output = NULL;
    args->tonemap = "clamp";
    args->width = args->height = 512;
    args->half = 0;
    args->exposure = 0;
}

int cli_image_check(const char *command, const cli_image_args *args) {
    if (!args->output)
        return cli_error(EXIT_USAGE, "%s: an output file is required (-o FILE)", command);
    if (args->width < 1 || args->width > CLI_IMAGE_MAX_SIDE || args->height < 1 ||
        args->height > CLI_IMAGE_MAX_SIDE)
        return cli_error(EXIT_USAGE, "%s: image size %dx%d: each side must be 1 to %d pixels",
                         command, args->width, args->height, CLI_IMAGE_MAX_SIDE);
    return 0;
}

int cli_image_check_path(rad_context *ctx, const cli_image_args *args, rad_image_save_options *save) {
    *save = (rad_image_save_options){args->exposure, args->tonemap, args->half};
    rad_status rs = rad_image_check_path(ctx, args->output, save);
    if (!rs) return 0;
    /* A bad extension or tone curve is a usage error; an unwritable place is not. */
    int usage = rs == RAD_ERROR_INVALID_ARGUMENT;
    cli_fail(ctx, rs);
    return usage ? EXIT_USAGE : 1;
}

int cli_image_open(const char *command, const cli_image_args *args, int threads, uint64_t seed,
                   double max_memory_mib, int quiet, const char *scene_name, cli_image_run *run) {
    run->ctx = cli_context_with_progress(threads, seed, max_memory_mib, quiet);
    run->scene = NULL;
    int status = cli_image_check_path(run->ctx, args, &run->save);
    if (!status) {
        run->status = cli_load_scene(run->ctx, scene_name, &run->scene);
        /* The output may be one of the scene's own files (its .mtl, .bin, a texture, ...). */
        if (!run->status)
            status = cli_check_outputs_against_scene(command, run->scene, &args->output, 1);
    }
    if (status) cli_image_close(run);
    return status;
}

void cli_image_write(cli_image_run *run, const cli_image_args *args, const rad_image *image,
                     double *seconds) {
    *seconds = 0;
    if (!run->status) {
        double start = cli_seconds();
        run->status = rad_image_save(image, args->output, &run->save);
        *seconds = cli_seconds() - start;
    }
    cli_progress_clear();
}

void cli_image_close(cli_image_run *run) {
    rad_scene_destroy(run->scene);
    rad_context_destroy(run->ctx);
    run->scene = NULL;
    run->ctx = NULL;
}
