/* cmd_scenes.c - `radiosity scenes`: lists the built-in scenes; with --export, writes a
 * geometric scene (a built-in name or any file the importer reads) as OBJ + MTL. */
#include "cli.h"
#include "output_path.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* --generate KIND TRIANGLES FILE.obj. */
static int cli_scenes_generate(const char *kind, const char **positional, int count, int quiet) {
    if (strcmp(kind, "house") == 0) {
        if (count != 1)
            return cli_error(EXIT_USAGE, "scenes: --generate house needs an output file (usage: "
                             "radiosity scenes --generate house FILE.obj)");
        int status = cli_check_output_path("scenes", positional[0], NULL, 0);
        if (status) return status;
        rad_context *ctx = cli_context(1, 0, 0, quiet);
        rad_scene *scene = NULL;
        rad_status rs = rad_scene_generate_house(ctx, &scene);
        if (!rs) rs = rad_scene_export_obj(ctx, scene, positional[0]);
        int exit_status = rs ? cli_fail(ctx, rs) : 0;
        rad_scene_destroy(scene);
        rad_context_destroy(ctx);
        return exit_status;
    }
    if (strcmp(kind, "office") != 0)
        return cli_error(EXIT_USAGE, "scenes: unknown generator '%s' (office, house)", kind);
    if (count != 2)
        return cli_error(EXIT_USAGE, "scenes: --generate office needs a triangle count and an "
                         "output file (usage: radiosity scenes --generate office TRIANGLES FILE.obj)");
    char *end;
    errno = 0;
    unsigned long long triangles = strtoull(positional[0], &end, 10);
    if (end == positional[0] || *end || errno || positional[0][0] == '-' || triangles < 123 ||
        triangles > 200000000)
        return cli_error(EXIT_USAGE, "scenes: the triangle count must be a whole number from 123 "
                         "to 200000000, not '%s'", positional[0]);
    int status = cli_check_output_path("scenes", positional[1], NULL, 0);
    if (status) return status;
    rad_context *ctx = cli_context(1, 0, 0, quiet);
    rad_scene *scene = NULL;
    rad_status rs = rad_scene_generate_office(ctx, (size_t)triangles, &scene);
    if (!rs) rs = rad_scene_export_obj(ctx, scene, positional[1]);
    int exit_status = rs ? cli_fail(ctx, rs) : 0;
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}

int cmd_scenes(int argc, char **argv) {
    static const char synopsis[] = "[--export SCENE FILE.obj | --generate office TRIANGLES "
                                   "FILE.obj | --generate house FILE.obj]   (without options: list the built-in scenes)";
    const char *export_scene = NULL, *generate = NULL;
    int quiet = 0;
    const cli_option options[] = {
        {"--export", CLI_STRING, &export_scene,
         "SCENE FILE.obj  write a geometric scene (built-in or file) as OBJ, with FILE.mtl"},
        {"--generate", CLI_STRING, &generate,
         "office TRIANGLES FILE.obj  write a generated lit open-plan office of about that many "
         "triangles; house FILE.obj: a closed two-room house on a slab (leak test)"},
        {"--quiet", CLI_FLAG, &quiet, "no notes on stderr"},
        {0},
    };
    const char *positional[2];
    int count;
    int status = cli_parse("scenes", synopsis, options, argc, argv, positional, 2, &count);
    if (status) return status < 0 ? 0 : status;
    if (generate) return cli_scenes_generate(generate, positional, count, quiet);
    if (!export_scene) {
        if (count)
            return cli_error(EXIT_USAGE, "scenes: unexpected argument '%s' (usage: radiosity "
                             "scenes %s)", positional[0], synopsis);
        for (size_t i = 0; i < rad_builtin_scene_count(); ++i)
            printf("%-16s %s\n", rad_builtin_scene_name(i), rad_builtin_scene_description(i));
        return 0;
    }
    if (count > 1)
        return cli_error(EXIT_USAGE, "scenes: unexpected argument '%s' (usage: radiosity scenes "
                         "%s)", positional[1], synopsis);
    if (count != 1)
        return cli_error(EXIT_USAGE, "scenes: --export needs a scene and an output file "
                         "(usage: radiosity scenes --export SCENE FILE.obj)");
    if ((status = cli_check_output_path("scenes", positional[0], &export_scene, 1))) return status;

    rad_context *ctx = cli_context(1, 0, 0, quiet);
    rad_scene *scene = NULL;
    rad_status rs = cli_load_scene(ctx, export_scene, &scene);
    if (!rs) rs = rad_scene_export_obj(ctx, scene, positional[0]);
    int exit_status = rs ? cli_fail(ctx, rs) : 0;
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
