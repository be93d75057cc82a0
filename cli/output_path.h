/* output_path.h - an output file must never be one of the command's inputs: writing it would
 * destroy the input (and, with temp + rename, silently replace it). */
#ifndef RAD_CLI_OUTPUT_PATH_H
#define RAD_CLI_OUTPUT_PATH_H

#include <stddef.h>

typedef struct rad_scene rad_scene;

/* Prints a usage error and returns EXIT_USAGE when `output` is the same file as one of the
 * inputs (the same device and inode, so another spelling or a link counts too); 0 otherwise.
 * NULL outputs and inputs are skipped, as are inputs that are not files (built-in scene names). */
int cli_check_output_path(const char *command, const char *output, const char *const *inputs,
                          size_t input_count);

/* After the scene is loaded: the same refusal when an output is one of the files the scene was
 * read from (rad_scene_file: its .mtl, .bin, textures, MGF includes, IES profiles), and the
 * same for the file written beside an output (FILE.bin of a .gltf, FILE.mtl of an .obj).
 * NULL outputs are skipped. */
int cli_check_outputs_against_scene(const char *command, const rad_scene *scene,
                                    const char *const *outputs, size_t output_count);

#endif
