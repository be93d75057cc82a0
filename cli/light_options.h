/* light_options.h - the light flags of the commands that solve or draw a scene (solve, render,
 * bake, pathtrace): --sky, --sun and --ies (docs/lights.md), and --two-sided (also photonmap and
 * scenes --info). Checked with the other flags (a
 * usage error, exit 2), then applied to the scene as it is loaded (cli_load_scene), before any
 * system is built from it. */
#ifndef RAD_CLI_LIGHT_OPTIONS_H
#define RAD_CLI_LIGHT_OPTIONS_H

#include "cli.h"

typedef struct cli_light_args {
    const char *sky, *sun, *ies; /* as given; NULL when not */
    rad_sky_desc sky_desc;
    rad_light_desc sun_desc;
    char ies_name[256];
    const char *ies_path;
    const char *specular_first, *specular_photons; /* as given; NULL when not */
    int specular_on;                                /* 1, 0, or -1: when mirrors or glass */
    unsigned long long specular_photon_count;       /* 0: the default */
    int two_sided;                                  /* --two-sided */
} cli_light_args;

/* The three entries of an option table: write CLI_LIGHT_OPTIONS(&args) among a command's own. */
#define CLI_LIGHT_OPTIONS(args)                                                                   \
    {"--sky", CLI_STRING, &(args)->sky,                                                           \
     "[uniform:|cie-overcast:]L  sky radiance L (or R,G,B; overcast: at the zenith) above +Y"},   \
    {"--sun", CLI_STRING, &(args)->sun,                                                           \
     "X,Y,Z,E  sun towards X,Y,Z with irradiance E (W/m^2)"},                                     \
    {"--ies", CLI_STRING, &(args)->ies, "[NAME=]FILE  IES LM-63 profile for light NAME (all)"}

/* The specular-first flags of solve, render and bake (docs/specular-first.md). */
#define CLI_SPECULAR_OPTIONS(args)                                                                \
    {"--specular-first", CLI_STRING, &(args)->specular_first,                                     \
     "1|0  light through mirrors and glass as emission before the solve (default: 1 when the "    \
     "scene has mirrors or glass)"},                                                              \
    {"--specular-photons", CLI_STRING, &(args)->specular_photons,                                 \
     "N  photons of the specular-first pass (default 1000000)"}

/* --two-sided (rad_scene_set_two_sided), applied with the light flags as the scene loads. */
#define CLI_TWO_SIDED_OPTION(args)                                                                \
    {"--two-sided", CLI_FLAG, &(args)->two_sided,                                                 \
     "both faces of every surface receive and reflect (emitters and glass excepted)"}

/* Checks the values (usage error: message printed, EXIT_USAGE; 0 when fine) and registers the
 * flags so that cli_load_scene applies them to the scene it loads. */
int cli_lights_check(const char *command, cli_light_args *args);

/* Applies the registered flags to a loaded scene (nothing when none were checked). */
rad_status cli_lights_apply(rad_scene *scene);

#endif
