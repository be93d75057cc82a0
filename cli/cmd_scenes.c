/* cmd_scenes.c - `radiosity scenes`: the built-in scenes. */
#include "cli.h"

int cmd_scenes(int argc, char **argv) {
    static const char synopsis[] = "";
    const cli_option options[] = {{0}};
    const char *positional[1];
    int count;
    int status = cli_parse("scenes", synopsis, options, argc, argv, positional, 0, &count);
    if (status) return status < 0 ? 0 : status;
    for (size_t i = 0; i < rad_builtin_scene_count(); ++i)
        printf("%-16s %s\n", rad_builtin_scene_name(i), rad_builtin_scene_description(i));
    return 0;
}
