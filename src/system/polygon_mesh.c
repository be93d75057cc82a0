/* polygon_mesh.c - the coarsest mesh: one element per root of the hierarchy (mesh/roots.h: each
 * input polygon cut at its contacts, the hidden pieces dropped, quads and triangles as they
 * are, larger pieces fanned), one patch per element, four vertices of its own per element (no
 * welding). It is what a system needs when its solver refines and draws its own leaves
 * (RAD_SOLVER_OWN_LEAVES: the hierarchical solver's quadtree roots are exactly these
 * elements, in the same order); linear in the polygon count. */
#include "system/system.h"

#include "mesh/mesh.h"
#include "mesh/roots.h"
#include "scene/scene.h"

#include <string.h>

rad_status rad_system_polygon_mesh(rad_context *ctx, const rad_scene *scene, rad_mesh **out) {
    *out = NULL;
    rad_roots *roots = NULL;
    rad_status status = rad_roots_create(ctx, scene, 0, &roots);
    if (status) return status;
    size_t elements = roots->count;
    rad_mesh *m = rad_mesh_alloc(ctx, 4 * elements, elements);
    if (!m) {
        rad_roots_destroy(ctx, roots);
        return rad_fail(ctx, RAD_ERROR_NO_MEMORY, "out of memory for a mesh of %zu polygons",
                        elements);
    }
    double total = 0;
    size_t nv = 0;
    for (size_t e = 0; e < elements; ++e) {
        const rad_root *root = &roots->roots[e];
        const rad_polygon *polygon = &scene->polygons[root->polygon];
        rad_vec3 centroid = v3(0, 0, 0);
        for (uint32_t i = 0; i < 4; ++i) {
            if (i >= root->count) {
                m->element_vertices[e][i] = RAD_NO_VERTEX;
                continue;
            }
            m->vertices[nv] = root->corner[i];
            m->vertex_surface[nv] = polygon->surface;
            m->element_vertices[e][i] = (uint32_t)nv++;
            centroid = v3_add(centroid, root->corner[i]);
        }
        m->element_normal[e] = rad_polygon_normal(scene, polygon);
        m->element_centroid[e] = v3_scale(centroid, 1.0 / root->count);
        m->element_area[e] = root->area;
        m->element_polygon[e] = root->polygon;
        m->element_surface[e] = polygon->surface;
        m->element_patch[e] = (uint32_t)e;
        m->patch_first[e] = e;
        total += root->area;
    }
    rad_roots_destroy(ctx, roots);
    m->vertex_count = nv;
    m->element_count = m->patch_count = elements;
    m->patch_first[elements] = elements;
    m->element_size = m->patch_size = elements ? sqrt(total / (double)elements) : 0;
    if (elements == 0) {
        rad_mesh_destroy(m);
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s: no polygon with a nonzero area",
                        scene->source);
    }
    *out = m;
    return RAD_OK;
}
