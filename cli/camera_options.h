/* camera_options.h - the camera flags of the commands that make an image of a scene (render,
 * pathtrace): --eye, --look, --up and --fov, each overriding one part of the scene's own camera
 * (or of the one that frames a scene without a camera). */
#ifndef RAD_CLI_CAMERA_OPTIONS_H
#define RAD_CLI_CAMERA_OPTIONS_H

#include "cli.h"

typedef struct cli_camera_args {
    double eye[3], look[3], up[3]; /* NaN in [0] when not given */
    double fov;                    /* vertical, degrees; NaN when not given */
} cli_camera_args;

/* The four entries of an option table, in --help order: write CLI_CAMERA_OPTIONS(&args) among a
 * command's own options. */
#define CLI_CAMERA_OPTIONS(args)                                                                  \
    {"--eye", CLI_VEC3, (args)->eye, "X,Y,Z  camera position (the scene's camera)"},              \
    {"--look", CLI_VEC3, (args)->look, "X,Y,Z  point the camera looks at"},                        \
    {"--up", CLI_VEC3, (args)->up, "X,Y,Z  up direction"},                                         \
    {"--fov", CLI_DOUBLE, &(args)->fov, "DEG  vertical field of view"}

/* Nothing given: the scene's camera as it is. */
void cli_camera_args_init(cli_camera_args *args);

/* Prints a usage error and returns EXIT_USAGE for a field of view outside (0, 180); 0 otherwise.
 * (Vectors are checked by the option parser.) */
int cli_camera_check(const char *command, const cli_camera_args *args);

/* The scene's camera with the given flags in place of its parts. */
void cli_camera_get(const cli_camera_args *args, const rad_scene *scene, rad_camera_desc *camera);

#endif
