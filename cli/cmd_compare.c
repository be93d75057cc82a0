/* cmd_compare.c - `radiosity compare`. PLACEHOLDER: being written in this session; not a finished
 * command until this comment is gone. */
#include "cli.h"

int cmd_compare(int argc, char **argv) {
    (void)argc;
    (void)argv;
    return cli_error(1, "compare: not available in this build yet");
}
