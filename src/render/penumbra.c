/* penumbra.c - which elements the emitters light unevenly (a shadow's edge crosses them, or the
 * lamp stands at their horizon), so the final gather spends its emitter samples there.
 *
 * The direct light's noise is the emitter samples' where the share of the lamp a point sees
 * varies (penumbras); where it sees all of it or none the light varies little over the lamp,
 * and a few stratified samples (a net over the lamp: emitters_build.c) get it. So the element
 * each pixel corner's camera ray meets is tested from PENUMBRA_POINTS points (its centroid and
 * its corners, a little inside) against a fixed set of points on the emitters (the lamp's
 * corners, edge middles and centre when the table is one parallelogram or triangle, else
 * LAMP_SPREAD points spread over the table by power): the element is uneven when some pairs see
 * each other (in front of both, unoccluded) and some do not. Render.c gives pixels whose
 * corners all meet even elements fewer emitter samples. Only the number of samples depends on
 * this test, never their weight, so the estimate stays unbiased whatever it misses (a small
 * occluder between the test points). Deterministic: the same for any thread count.
 *
 * The final gather also asks, for the elements its short rays meet (final_gather.c: only onto
 * unevenly lit elements, or elements near another surface, are they gathered again from afar).
 * Each element is tested once, when first asked, and the answer kept (element_uneven): until
 * arcade2 every element was, before the picture, though no other element's answer was read
 * (Sponza's 209,507 hierarchy leaves, up to 45 shadow rays each, against its 19,481 pixel
 * corners). */
#include "render/render.h"

#include <stdatomic.h>

#define LAMP_GRID 3     /* lamp points per side on a one-entry table */
#define LAMP_SPREAD RAD_PENUMBRA_LAMPS /* lamp points on a larger table */
#define PENUMBRA_POINTS 5
#define INSET 0.02      /* corners moved this share of the way to the centroid */

int rad_penumbra_lamps(const rad_renderer *r, rad_vec3 *points) {
    const rad_emitter_table *table = &r->emitters;
    if (r->settings.final_gather <= 0 || table->count == 0) return 0;
    int count = 0;
    if (table->count == 1) {
        static const double at[LAMP_GRID] = {1e-3, 0.5, 1 - 1e-3};
        for (int i = 0; i < LAMP_GRID; ++i)
            for (int j = 0; j < LAMP_GRID; ++j)
                rad_emitter_table_sample_point(table, at[i], at[j], &points[count++]);
        return count;
    }
    for (int i = 0; i < LAMP_SPREAD; ++i) {
        double u1 = (double)i * 0.6180339887498949;
        rad_emitter_table_sample_point(table, (i + 0.5) / LAMP_SPREAD, u1 - floor(u1), &points[count++]);
    }
    return count;
}

int rad_penumbra_uneven(const rad_renderer *r, uint32_t e, const rad_vec3 *lamp, int lamps) {
    if (lamps <= 0) return 0;
    const double *emission = rad_renderer_material(r, e)->emission;
    if (emission[0] > 0 || emission[1] > 0 || emission[2] > 0) return 0;
    const rad_mesh *mesh = r->mesh;
    rad_vec3 centroid = mesh->element_centroid[e], normal = mesh->element_normal[e];
    rad_vec3 points[PENUMBRA_POINTS];
    int count = rad_mesh_corner_count(mesh, e) + 1;
    points[0] = centroid;
    for (int k = 1; k < count; ++k) {
        rad_vec3 corner = mesh->vertices[mesh->element_vertices[e][k - 1]];
        points[k] = v3_add(corner, v3_scale(v3_sub(centroid, corner), INSET));
    }
    int lit = 0, dark = 0;
    for (int k = 0; k < count; ++k)
        for (int l = 0; l < lamps; ++l) {
            rad_vec3 to_lamp = v3_sub(lamp[l], points[k]);
            /* In front by more than rounding: a lamp in the element's own plane (a ceiling
             * lamp seen from the ceiling) is behind it at every scale of the scene. */
            int seen = v3_dot(to_lamp, normal) > 1e-9 * v3_length(to_lamp) &&
                       !rad_element_rays_occluded(r->inner_rays, points[k], lamp[l]);
            if (seen) ++lit;
            else ++dark;
            if (lit && dark) return 1;
        }
    return 0;
}

rad_status rad_penumbra_prepare(rad_renderer *r) {
    r->penumbra_lamps = rad_penumbra_lamps(r, r->penumbra_lamp);
    r->element_uneven = rad_alloc_zero(r->ctx, r->mesh->element_count + 1, sizeof *r->element_uneven);
    return r->element_uneven ? RAD_OK : RAD_ERROR_NO_MEMORY;
}

/* Two threads that ask at once both test and store the same answer. */
int rad_penumbra_element_uneven(const rad_renderer *r, uint32_t e) {
    uint8_t known = atomic_load_explicit(&r->element_uneven[e], memory_order_relaxed);
    if (known) return known == 2;
    int uneven = rad_penumbra_uneven(r, e, r->penumbra_lamp, r->penumbra_lamps);
    atomic_store_explicit(&r->element_uneven[e], (uint8_t)(1 + uneven), memory_order_relaxed);
    return uneven;
}
