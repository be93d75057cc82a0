/* cmd_compare.c - `radiosity compare TEST REF`: how far a test image is from a reference
 * (docs/images.md): RMSE, relative MSE (pbrt), PSNR, the ratio of the means; --diff writes a
 * false-colour map of the per-pixel relative error. */
#include "cli.h"
#include "output_path.h"
#include "json.h"

#include <math.h>

typedef struct compare_args {
    const char *diff;
    double scale;
    int json;
} compare_args;

int cmd_compare(int argc, char **argv) {
    static const char synopsis[] = "TEST REF [--diff FILE] [--json]   (TEST, REF: .pfm, .hdr or .exr)";
    compare_args a = {0};
    const cli_option options[] = {
        {"--diff", CLI_STRING, &a.diff, "FILE  false-colour map of the relative error (.png ...)"},
        {"--scale", CLI_DOUBLE, &a.scale,
         "E  relative error shown at the top of the colour scale (99th percentile)"},
        {"--json", CLI_FLAG, &a.json, "print one JSON object"},
        {NULL, 0, NULL, NULL},
    };
    const char *positional[2];
    int positional_count;
    int status = cli_parse("compare", synopsis, options, argc, argv, positional, 2, &positional_count);
    if (status) return status < 0 ? 0 : status;
    if (positional_count != 2)
        return cli_error(EXIT_USAGE, "compare: needs two images (usage: radiosity compare %s)",
                         synopsis);
    if (a.scale < 0) return cli_error(EXIT_USAGE, "compare: --scale must be positive");
    if ((status = cli_check_output_path("compare", a.diff, positional, 2))) return status;

    rad_context *ctx = cli_context(1, 0, 0, 1);
    rad_status rs = RAD_OK;
    if (a.diff) {
        rs = rad_image_check_path(ctx, a.diff, NULL);
        if (rs) {
            int usage = rs == RAD_ERROR_INVALID_ARGUMENT;
            cli_fail(ctx, rs);
            rad_context_destroy(ctx);
            return usage ? EXIT_USAGE : 1;
        }
    }
    rad_image *test = NULL, *reference = NULL, *map = NULL;
    rad_image_comparison c;
    double scale = a.scale;
    rs = rad_image_read(ctx, positional[0], &test);
    if (!rs) rs = rad_image_read(ctx, positional[1], &reference);
    if (!rs) rs = rad_image_compare(ctx, test, reference, &c);
    if (!rs && a.diff) rs = rad_image_error_map(ctx, test, reference, &scale, &map);
    if (!rs && a.diff) rs = rad_image_save(map, a.diff, NULL);
    int exit_status = 0;
    if (rs) {
        exit_status = cli_fail(ctx, rs);
    } else if (a.json) {
        printf("{\"width\": %d, \"height\": %d, \"rmse\": ", rad_image_width(test),
               rad_image_height(test));
        json_number(stdout, c.rmse);
        printf(", \"relative_mse\": ");
        json_number(stdout, c.relative_mse);
        printf(", \"psnr\": ");
        json_number(stdout, c.psnr); /* null when the images are identical */
        printf(", \"mean_test\": ");
        json_number(stdout, c.mean_test);
        printf(", \"mean_reference\": ");
        json_number(stdout, c.mean_reference);
        printf(", \"mean_ratio\": ");
        json_number(stdout, c.mean_ratio);
        if (a.diff) {
            printf(", \"diff\": ");
            json_string(stdout, a.diff);
            printf(", \"diff_scale\": ");
            json_number(stdout, scale);
        }
        printf("}\n");
    } else {
        printf("size          %dx%d\n", rad_image_width(test), rad_image_height(test));
        printf("rmse          %.6g\n", c.rmse);
        printf("relative mse  %.6g\n", c.relative_mse);
        if (isinf(c.psnr)) printf("psnr          inf (identical)\n");
        else printf("psnr          %.4g dB (peak 1)\n", c.psnr);
        printf("mean          %.6g (test) / %.6g (reference) = %.6g\n", c.mean_test,
               c.mean_reference, c.mean_ratio);
        if (a.diff) printf("diff          %s (relative error 0 .. %.3g)\n", a.diff, scale);
    }
    rad_image_destroy(map);
    rad_image_destroy(test);
    rad_image_destroy(reference);
    rad_context_destroy(ctx);
    return exit_status;
}
