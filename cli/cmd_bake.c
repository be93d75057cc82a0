/* cmd_bake.c - `radiosity bake`. PLACEHOLDER: being written in this session; not a finished
 * command until this comment is gone. */
#include "cli.h"

int cmd_bake(int argc, char **argv) {
    (void)argc;
    (void)argv;
    return cli_error(1, "bake: not available in this build yet");
}
