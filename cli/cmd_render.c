/* cmd_render.c - `radiosity render`. PLACEHOLDER: being written in this session; not a finished
 * command until this comment is gone. */
#include "cli.h"

int cmd_render(int argc, char **argv) {
    (void)argc;
    (void)argv;
    return cli_error(1, "render: not available in this build yet");
}
