/* solve_snapshots.c - --snapshots DIR --snapshot-every K: an image of the solution as it is
 * after every K shots or rounds, DIR/snapshot-NNNNNN.png, rendered with the ambient term
 * (Cohen et al. 1988) so early images show the light still to come as a uniform glow rather
 * than black. The renderer is built once; each snapshot re-reads the current solution. */
#include "cli.h"
#include "solve_cli.h"

#include <stdlib.h>
#include <string.h>

struct solve_snapshots {
    rad_context *ctx;
    rad_renderer *renderer;
    const char *dir;
    rad_image_save_options save;
};

int solve_snapshots_create(rad_context *ctx, const rad_scene *scene, const rad_system *system,
                           const solve_args *a, const rad_camera_desc *camera,
                           solve_snapshots **out) {
    *out = NULL;
    solve_snapshots *s = calloc(1, sizeof *s);
    if (!s) return cli_error(1, "out of memory");
    s->ctx = ctx;
    s->dir = a->snapshots;
    s->save.exposure = a->exposure;
    s->save.tonemap = a->tonemap;
    rad_render_options options = {0};
    options.width = a->width ? a->width : 256;
    options.height = a->height ? a->height : 256;
    options.camera = camera;
    options.ambient = 1;
    char probe[64];
    snprintf(probe, sizeof probe, "%s/snapshot.png", a->snapshots);
    rad_status status = rad_image_check_path(ctx, probe, &s->save);
    if (!status) status = rad_renderer_create(scene, system, &options, &s->renderer);
    if (status) {
        free(s);
        return cli_fail(ctx, status);
    }
    *out = s;
    return 0;
}

int solve_snapshot_take(void *user, long step) {
    solve_snapshots *s = user;
    size_t length = strlen(s->dir) + 40;
    char *path = malloc(length);
    if (!path) return cli_error(1, "out of memory");
    snprintf(path, length, "%s/snapshot-%06ld.png", s->dir, step);
    rad_image *image = NULL;
    rad_status status = rad_renderer_render(s->renderer, &image, NULL);
    if (!status) status = rad_image_save(image, path, &s->save);
    rad_image_destroy(image);
    free(path);
    return status ? cli_fail(s->ctx, status) : 0;
}

void solve_snapshots_destroy(solve_snapshots *s) {
    if (!s) return;
    rad_renderer_destroy(s->renderer);
    free(s);
}
