/* cmd_formfactors.c - `radiosity formfactors`. PLACEHOLDER: being written in this session; not a finished
 * command until this comment is gone. */
#include "cli.h"

int cmd_formfactors(int argc, char **argv) {
    (void)argc;
    (void)argv;
    return cli_error(1, "formfactors: not available in this build yet");
}
