/* bench_progressive.c - the solver comparison on the Cornell box at 10,000 elements: runs
 * `radiosity solve cornell --elements 10000 --compare-solvers --plot solver-comparison.svg`
 * with the radiosity tool built beside this program, which prints the time each solver needs to
 * 1% error (docs/solvers.md, "Comparing the solvers"). The chart is written to the current
 * directory. Timings only: nothing here passes or fails. bench/README.md, "Solver comparison",
 * keeps the measured table and chart. Takes a few minutes on 2 cores.
 * Usage: bench_progressive [ELEMENTS] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv) {
    const char *elements = argc > 1 ? argv[1] : "10000";
    char tool[4096];
    const char *slash = strrchr(argv[0], '/');
    int dir = slash ? (int)(slash - argv[0]) : 1;
    snprintf(tool, sizeof tool, "%.*s/radiosity", dir, slash ? argv[0] : ".");
    char command[8192];
    snprintf(command, sizeof command,
             "'%s' solve cornell --elements '%s' --compare-solvers --quiet "
             "--eye 186,200,-100 --look 186,80,170 --fov 30 --plot solver-comparison.svg",
             tool, elements);
    printf("## Solver comparison: Cornell box, %s elements (chart: solver-comparison.svg)\n\n",
           elements);
    fflush(stdout);
    int status = system(command);
    return status == 0 ? 0 : 1;
}
