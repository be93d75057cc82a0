/* fuzz_import.c - libFuzzer target for scene files through the importer (src/scene/import.c,
 * the header checks of src/scene/import_check.c, and assimp behind them): whatever a file
 * holds, loading it gives a scene or an error, in bounded time and memory. The first byte picks
 * the extension (.ply, .glb, .obj, .gltf); the rest is written to a temporary file. (Meshing
 * is left to the other tests: building Embree scenes would cut the rate by ten.) The import runs
 * in this process (rad_scene_import_here), not in the child process rad_scene_load starts, so
 * the fuzzer sees what assimp and the project's own walk do. */
#include "input_file.h"
#include "radiosity.h"
#include "scene/scene.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *const extensions[] = {"ply", "glb", "obj", "gltf"};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    const char *path = fuzz_write_input(extensions[data[0] & 3], data + 1, size - 1);

    rad_context_options options = {0};
    options.threads = 1;
    options.max_memory = 64u << 20;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 0;
    rad_scene *scene = NULL;
    if (rad_scene_import_here(ctx, path, &scene) == RAD_OK) {
        rad_camera_desc camera;
        rad_scene_get_camera(scene, &camera);
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
