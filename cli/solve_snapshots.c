/* solve_snapshots.c - --snapshots DIR --snapshot-every K: an image of the solution as it is
 * after every K shots or rounds, DIR/snapshot-NNNNNN.png, rendered with the ambient term
 * (Cohen et al. 1988) so early images show the light still to come as a uniform glow rather
 * than black. The renderer is built once; each snapshot re-reads the current solution. */
#include "cli.h"
#include "output_path.h"
#include "solve_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct solve_snapshots {
    rad_context *ctx;
    rad_renderer *renderer;
    const char *dir;
    rad_image_save_options save;
};

/* A scene file (a texture, say) named like a snapshot in DIR: refused before the solve starts
 * (exit 2), since some step would write over it. */
static int check_scene_files(const rad_scene *scene, const char *dir) {
    for (size_t i = 0; i < rad_scene_file_count(scene); ++i) {
        const char *file = rad_scene_file(scene, i);
        const char *base = strrchr(file, '/');
        base = base ? base + 1 : file;
        long step;
        int end = 0;
        if (sscanf(base, "snapshot-%6ld.png%n", &step, &end) != 1 || base[end] != '\0') continue;
        size_t length = strlen(dir) + strlen(base) + 2;
        char *path = malloc(length);
        if (!path) return cli_error(1, "out of memory");
        snprintf(path, length, "%s/%s", dir, base);
        const char *outputs[1] = {path};
        int refused = cli_check_outputs_against_scene("solve", scene, outputs, 1);
        free(path);
        if (refused) return refused;
    }
    return 0;
}

int solve_snapshots_create(rad_context *ctx, const rad_scene *scene, const rad_system *system,
                           const solve_args *a, const rad_camera_desc *camera,
                           solve_snapshots **out) {
    *out = NULL;
    int refused = check_scene_files(scene, a->snapshots);
    if (refused) return refused;
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
