/* fuzz_gltf.c - libFuzzer target for the project's own glTF reading (src/scene/gltf_extras.c:
 * the binary glTF chunk header and a JSON walker that picks out emissive strengths and camera
 * fields of view). The input is written to a temporary file, since the reader takes a path;
 * "glTF" at its start makes it a .glb. */
#include "input_file.h"
#include "scene/gltf_extras.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const char *path = fuzz_write_input("gltf", data, size);

    rad_context_options options = {0};
    options.max_memory = 64u << 20;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return 0;
    rad_gltf_extras extras = {0};
    if (rad_gltf_extras_read(ctx, path, &extras) == RAD_OK) {
        /* Every entry the reader reports must be there. */
        double sum = 0;
        for (size_t i = 0; i < extras.material_count; ++i) sum += extras.emissive_strength[i];
        for (size_t i = 0; i < extras.camera_count; ++i) sum += extras.camera_yfov[i];
        (void)sum;
    }
    rad_gltf_extras_free(ctx, &extras);
    rad_context_destroy(ctx);
    return 0;
}
