/* fuzz_mgf.c - libFuzzer target for the MGF reader (src/scene/mgf.c): whatever the text, loading
 * gives a scene whose polygons all have finite vertices in range, or one error, in bounded time
 * and memory; includes resolve beside the input (a file that includes itself stops at the
 * nesting limit). */
#include "input_file.h"
#include "scene/mgf.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const char *path = fuzz_write_input("mgf", data, size);
    rad_context_options context_options = {.threads = 1, .max_memory = 64u << 20};
    rad_context *ctx = NULL;
    if (rad_context_create(&context_options, &ctx)) return 0;
    rad_scene *scene = NULL;
    if (rad_scene_load_mgf(ctx, path, &scene) == RAD_OK) {
        if (scene->polygon_count == 0) abort(); /* an empty scene is an error */
        for (size_t i = 0; i < scene->polygon_count; ++i) {
            const rad_polygon *polygon = &scene->polygons[i];
            if (polygon->count < 3 || polygon->surface >= scene->surface_count) abort();
            for (uint32_t k = 0; k < polygon->count; ++k) {
                rad_vec3 p = rad_polygon_vertex(scene, polygon, k);
                if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) abort();
            }
        }
    }
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return 0;
}
