/* polygon_mesh.c - the coarsest mesh: one element per input polygon (quads and triangles as
 * they are, larger convex polygons fanned into triangles from their first corner), one patch
 * per element, the scene's own vertices, no contact cuts and no welding. It is what a system
 * needs when its solver refines and draws its own leaves (RAD_SOLVER_OWN_LEAVES: the
 * hierarchical solver's quadtree roots are exactly these polygons); linear in the polygon
 * count. */
#include "system/system.h"

#include "mesh/mesh.h"
#include "scene/scene.h"

#include <string.h>

static double corner_area(rad_vec3 a, rad_vec3 b, rad_vec3 c, rad_vec3 d, int count) {
    if (count == 3) return 0.5 * v3_length(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    return 0.5 * v3_length(v3_cross(v3_sub(c, a), v3_sub(d, b)));
}

rad_status rad_system_polygon_mesh(rad_context *ctx, const rad_scene *scene, rad_mesh **out) {
    *out = NULL;
    size_t elements = 0;
    for (size_t p = 0; p < scene->polygon_count; ++p) {
        uint32_t n = scene->polygons[p].count;
        elements += n <= 4 ? 1 : n - 2;
    }
    size_t nv = scene->vertex_count;
    rad_mesh *m = rad_mesh_alloc(ctx, nv, elements);
    if (!m)
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for a mesh of %zu polygons",
                        elements);
    if (nv) memcpy(m->vertices, scene->vertices, nv * sizeof *m->vertices);
    m->vertex_count = nv;
    double total = 0;
    size_t e = 0;
    for (size_t p = 0; p < scene->polygon_count; ++p) {
        const rad_polygon *polygon = &scene->polygons[p];
        const uint32_t *ids = scene->polygon_vertices + polygon->first;
        uint32_t pieces = polygon->count <= 4 ? 1 : polygon->count - 2;
        rad_vec3 normal = rad_polygon_normal(scene, polygon);
        for (uint32_t k = 0; k < pieces; ++k) {
            int count = polygon->count == 4 ? 4 : 3;
            uint32_t corner[4] = {ids[0], ids[k + 1], ids[k + 2], count == 4 ? ids[3] : RAD_NO_VERTEX};
            rad_vec3 c[4], centroid = v3(0, 0, 0);
            for (int i = 0; i < 4; ++i) {
                c[i] = i < count ? scene->vertices[corner[i]] : c[0];
                if (i < count) centroid = v3_add(centroid, c[i]);
            }
            double area = corner_area(c[0], c[1], c[2], c[3], count);
            if (!(area > 0)) continue; /* degenerate: no element, as the mesher skips them */
            memcpy(m->element_vertices[e], corner, sizeof corner);
            for (int i = 0; i < count; ++i) m->vertex_surface[corner[i]] = polygon->surface;
            m->element_normal[e] = normal;
            m->element_centroid[e] = v3_scale(centroid, 1.0 / count);
            m->element_area[e] = area;
            m->element_polygon[e] = (uint32_t)p;
            m->element_surface[e] = polygon->surface;
            m->element_patch[e] = (uint32_t)e;
            m->patch_first[e] = e;
            total += area;
            ++e;
        }
    }
    m->element_count = m->patch_count = e;
    m->patch_first[e] = e;
    m->element_size = m->patch_size = e ? sqrt(total / (double)e) : 0;
    if (e == 0) {
        rad_mesh_destroy(m);
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: no polygon with a nonzero area",
                        scene->source);
    }
    *out = m;
    return RAD_OK;
}
