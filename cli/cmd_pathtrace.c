/* cmd_pathtrace.c - `radiosity pathtrace`. PLACEHOLDER: being written in this session; not a finished
 * command until this comment is gone. */
#include "cli.h"

int cmd_pathtrace(int argc, char **argv) {
    (void)argc;
    (void)argv;
    return cli_error(1, "pathtrace: not available in this build yet");
}
