/* screen_share.c - what a camera sees of a system: the share of the image each element covers.
 * One ray through the centre of every pixel, traced against the element mesh
 * (system/element_rays.h) so a hit names its element directly; only front sides count, since
 * the solution lives on the front. This is the emitted importance of Smits, Arvo & Salesin 1992
 * (importance.c) and the weight of the view error (docs/solvers.md, "Importance"). */
#include "system/screen_share.h"

#include "scene/camera.h"
#include "system/element_rays.h"
#include "mesh/mesh.h"
#include "scene/scene.h"

#include <string.h>

rad_status rad_system_screen_share(rad_system *s, const rad_camera_desc *desc, int width,
                                   int height, double *share) {
    if (!s || !desc || !share) return RAD_ERROR_INVALID_ARGUMENT;
    rad_context *ctx = s->ctx;
    if (!s->mesh)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "a patch system has no geometry for a camera to see; importance and view "
                        "errors need a geometric scene");
    if (width == 0 && height == 0) width = height = RAD_SCREEN_SHARE_SIZE;
    rad_camera camera = rad_camera_from_desc(desc);
    rad_view view;
    rad_status status = rad_view_make(ctx, &camera, width, height, &view);
    if (status) return status;
    rad_element_rays *rays = NULL;
    status = rad_element_rays_create(ctx, s->mesh, &rays);
    if (status) return status;
    size_t pixels = (size_t)width * (size_t)height;
    uint32_t *seen = rad_alloc(ctx, pixels, sizeof *seen);
    if (!seen) {
        rad_element_rays_destroy(rays);
        return RAD_ERROR_NO_MEMORY;
    }
    /* Each pixel writes its own slot: the result does not depend on the thread count. */
#pragma omp parallel for schedule(dynamic, 4) num_threads(rad_thread_count(ctx))
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            rad_vec3 direction = rad_view_direction(&view, x + 0.5, y + 0.5);
            rad_element_hit hit;
            uint32_t element = UINT32_MAX;
            if (rad_element_rays_intersect(rays, view.eye, direction, 0, INFINITY, &hit) &&
                hit.front)
                element = hit.element;
            seen[(size_t)y * (size_t)width + (size_t)x] = element;
        }
    }
    memset(share, 0, s->element_count * sizeof *share);
    for (size_t i = 0; i < pixels; ++i)
        if (seen[i] != UINT32_MAX) share[seen[i]] += 1.0 / (double)pixels;
    rad_free(ctx, seen);
    rad_element_rays_destroy(rays);
    return RAD_OK;
}

double rad_system_element_area(const rad_system *s, size_t element) {
    return s && element < s->element_count ? s->area[element] : 0;
}
