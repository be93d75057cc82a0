#!/usr/bin/env bash
# cli_layers.sh - the folders of src/ include each other without a cycle and cli/ uses only the
# public header (scripts/check-layers.sh, docs/architecture.md); and the check itself fails on
# a tree that has a cycle or a cli/ file reaching into src/. (Named cli_* so that CMake's glob
# of the shell tests runs it; it needs no binary.)
# Usage: cli_layers.sh RADIOSITY SOURCE_DIR
source "$(dirname "$0")/lib_cli.sh" "$@"
script="$source_dir/scripts/check-layers.sh"

bash "$script" "$source_dir" >"$work/graph"
check "the source tree has no include cycle" test $? -eq 0
cat "$work/graph"
check "the graph is drawn" grep -q "^system -> " "$work/graph"

# A tree with a cycle a -> b -> c -> a and a clean d -> a.
mkdir -p "$work/t1/src/a" "$work/t1/src/b" "$work/t1/src/c" "$work/t1/src/d"
echo '#include "b/b.h"' >"$work/t1/src/a/a.c"
echo '#include "c/c.h"' >"$work/t1/src/b/b.c"
echo '#include "a/a.h"' >"$work/t1/src/c/c.h"
echo '#include "a/a.h"' >"$work/t1/src/d/d.c"
bash "$script" "$work/t1" >"$work/out1"
check "a cycle fails" test $? -ne 0
check "the cycle is named" grep -q "cycle among" "$work/out1"
check "d is not in the cycle" bash -c "! grep 'cycle among' '$work/out1' | grep -q ' d'"
# Break it: the check passes.
echo '/* none */' >"$work/t1/src/c/c.h"
bash "$script" "$work/t1" >"$work/out2"
check "no cycle passes" test $? -eq 0
# cli/ reaching into the library's internals fails.
mkdir -p "$work/t1/cli"
echo '#include "a/a.h"' >"$work/t1/cli/x.c"
bash "$script" "$work/t1" >"$work/out3"
check "cli including src/ fails" test $? -ne 0
finish
