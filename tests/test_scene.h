/* test_scene.h - scenes the tests build in code: a new scene whose surfaces share one grey
 * material (the same reflectance in R, G and B), the common start of the meshing, contact and
 * shadow tests. Uses test.h's CHECK. */
#ifndef RAD_TEST_SCENE_H
#define RAD_TEST_SCENE_H

#include "radiosity.h"
#include "test.h"

/* A scene called `name` with one material of reflectance `rho` and `count` surfaces on it,
 * named `surfaces[i]`, their indices in `out[i]`. NULL (a CHECK failed) when it cannot. */
static inline rad_scene *test_grey_scene(rad_context *ctx, const char *name, double rho,
                                         const char *const *surfaces, int count, uint32_t *out) {
    rad_scene *scene = NULL;
    CHECK(rad_scene_new(ctx, 1, name, &scene) == RAD_OK);
    if (!scene) return NULL;
    rad_material grey = {0};
    grey.reflectance[0] = grey.reflectance[1] = grey.reflectance[2] = rho;
    uint32_t material = 0;
    CHECK(rad_scene_add_material(scene, &grey, &material) == RAD_OK);
    for (int i = 0; i < count; ++i)
        CHECK(rad_scene_add_surface(scene, surfaces[i], material, &out[i]) == RAD_OK);
    return scene;
}

#endif
