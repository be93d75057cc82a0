/* reconstruct.c - the radiosity solution as radiance at any point of the mesh.
 *
 * The solution is constant per element. Shown as it is ("flat") the element grid is visible;
 * Cohen et al. 1986 ("An efficient radiosity approach for realistic image synthesis") average
 * the radiosity of the elements around each vertex, weighted by area, and interpolate it across
 * each element ("smooth", Gouraud shading): bilinearly on quads, barycentrically on triangles.
 * Vertices are split at creases and never shared between surfaces (mesh/mesh.h), so a corner
 * between a wall and the floor keeps one value per side instead of blending the two.
 *
 * Averaging is right inside a surface, where a vertex sits in the middle of its elements, but on
 * the boundary of a surface (a wall meeting the ceiling, the edge of a block) the average of the
 * one row of elements there stands for the value half an element inside, and radiosity often
 * changes fastest right there (the light grazes the top of the walls, corners are darker). So a
 * boundary vertex takes instead the value at the vertex of a plane fitted by least squares to
 * the elements around it and their neighbours (two rows deep), which extrapolates the gradient to
 * the edge, as Cohen & Wallace 1993 (ch. 9, "Rendering") suggest for nodes on the boundary.
 *
 * Radiance = B / pi for a Lambertian surface; on an emitter B = E + reflected, so B / pi is the
 * emitted radiance plus the reflected one. */
#include "render/render.h"

#include <string.h>

/* At most this many elements take part in the fit at one vertex. */
#define FIT_MAX 64

/* Elements around each vertex, as compressed rows. */
typedef struct vertex_elements {
    uint32_t *first; /* vertex_count + 1 */
    uint32_t *element;
} vertex_elements;

static rad_status vertex_elements_build(rad_context *ctx, const rad_mesh *mesh, vertex_elements *out) {
    out->first = rad_alloc_zero(ctx, mesh->vertex_count + 1, sizeof *out->first);
    size_t uses = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) uses += (size_t)rad_mesh_corner_count(mesh, e);
    out->element = rad_alloc(ctx, uses + 1, sizeof *out->element);
    uint32_t *fill = rad_alloc(ctx, mesh->vertex_count + 1, sizeof *fill);
    if (!out->first || !out->element || !fill) {
        rad_free(ctx, fill);
        return RAD_ERROR_NO_MEMORY;
    }
    for (size_t e = 0; e < mesh->element_count; ++e)
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) out->first[mesh->element_vertices[e][k] + 1]++;
    for (size_t v = 0; v < mesh->vertex_count; ++v) out->first[v + 1] += out->first[v];
    memcpy(fill, out->first, mesh->vertex_count * sizeof *fill);
    for (size_t e = 0; e < mesh->element_count; ++e)
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k)
            out->element[fill[mesh->element_vertices[e][k]]++] = (uint32_t)e;
    rad_free(ctx, fill);
    return RAD_OK;
}

static int has_vertex(const rad_mesh *mesh, uint32_t element, uint32_t vertex) {
    for (int k = 0; k < rad_mesh_corner_count(mesh, element); ++k)
        if (mesh->element_vertices[element][k] == vertex) return 1;
    return 0;
}

/* Nonzero when an edge at v belongs to one element only: v is on the boundary of its surface. */
static int on_boundary(const rad_mesh *mesh, const vertex_elements *around, uint32_t v) {
    for (uint32_t i = around->first[v]; i < around->first[v + 1]; ++i) {
        uint32_t e = around->element[i];
        int n = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < n; ++k) {
            if (mesh->element_vertices[e][k] != v) continue;
            uint32_t neighbours[2] = {mesh->element_vertices[e][(k + 1) % n],
                                      mesh->element_vertices[e][(k + n - 1) % n]};
            for (int side = 0; side < 2; ++side) {
                int shared = 0;
                for (uint32_t j = around->first[v]; j < around->first[v + 1] && !shared; ++j)
                    shared = around->element[j] != e && has_vertex(mesh, around->element[j], neighbours[side]);
                if (!shared) return 1;
            }
        }
    }
    return 0;
}

/* The least-squares plane B(d) = a + g . d through the element values at their centroids
 * (offsets d in the tangent plane at the vertex, weights = areas) gives a = sum_i w_i B_i.
 * Returns the number of weights, or 0 when the centroids do not span the plane. */
static int fit_weights(const rad_mesh *mesh, uint32_t v, const uint32_t *elements, int count,
                       double *weight) {
    rad_vec3 normal = v3(0, 0, 0);
    double area = 0;
    for (int i = 0; i < count; ++i) {
        normal = v3_add(normal, v3_scale(mesh->element_normal[elements[i]], mesh->element_area[elements[i]]));
        area += mesh->element_area[elements[i]];
    }
    if (!(area > 0) || !(v3_length(normal) > 0)) return 0;
    rad_vec3 t, b;
    v3_basis(v3_normalize(normal), &t, &b);
    double scale = 1 / sqrt(area / count); /* offsets in element sizes */
    double m[3][3] = {{0}}, d[FIT_MAX][2];
    for (int i = 0; i < count; ++i) {
        rad_vec3 offset = v3_sub(mesh->element_centroid[elements[i]], mesh->vertices[v]);
        double row[3] = {1, v3_dot(offset, t) * scale, v3_dot(offset, b) * scale};
        double alpha = mesh->element_area[elements[i]] / area;
        d[i][0] = row[1];
        d[i][1] = row[2];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) m[j][k] += alpha * row[j] * row[k];
    }
    /* First row of the inverse, by cofactors. */
    double c0 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    double c1 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    double c2 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    double det = m[0][0] * c0 + m[0][1] * c1 + m[0][2] * c2;
    if (!(det > 1e-6)) return 0;
    for (int i = 0; i < count; ++i) {
        double alpha = mesh->element_area[elements[i]] / area;
        weight[i] = alpha * (c0 + c1 * d[i][0] + c2 * d[i][1]) / det;
    }
    return count;
}

rad_status rad_reconstruct_build(rad_renderer *r) {
    rad_context *ctx = r->ctx;
    const rad_mesh *mesh = r->mesh;
    vertex_elements around = {NULL, NULL};
    rad_status status = vertex_elements_build(ctx, mesh, &around);
    size_t capacity = 0, used = 0;
    uint8_t *boundary = rad_alloc_zero(ctx, mesh->vertex_count + 1, 1);
    if (!status && !boundary) status = RAD_ERROR_NO_MEMORY;
    for (size_t v = 0; v < mesh->vertex_count && !status; ++v)
        if (on_boundary(mesh, &around, (uint32_t)v)) {
            boundary[v] = 1;
            r->fit_count++;
        }
    if (!status) {
        r->fit_vertex = rad_alloc(ctx, r->fit_count + 1, sizeof *r->fit_vertex);
        r->fit_first = rad_alloc(ctx, r->fit_count + 1, sizeof *r->fit_first);
        r->fit_size = rad_alloc(ctx, r->fit_count + 1, sizeof *r->fit_size);
        capacity = 8 * r->fit_count + 1;
        r->fit_element = rad_alloc(ctx, capacity, sizeof *r->fit_element);
        r->fit_weight = rad_alloc(ctx, capacity, sizeof *r->fit_weight);
        if (!r->fit_vertex || !r->fit_first || !r->fit_size || !r->fit_element || !r->fit_weight)
            status = RAD_ERROR_NO_MEMORY;
    }
    size_t fit = 0;
    for (size_t v = 0; v < mesh->vertex_count && !status; ++v) {
        if (!boundary[v]) continue;
        /* The elements at v and their neighbours through any shared vertex. */
        uint32_t elements[FIT_MAX];
        int count = 0;
        for (uint32_t i = around.first[v]; i < around.first[v + 1]; ++i) {
            uint32_t e = around.element[i];
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
                uint32_t w = mesh->element_vertices[e][k];
                for (uint32_t j = around.first[w]; j < around.first[w + 1]; ++j) {
                    uint32_t candidate = around.element[j];
                    int seen = 0;
                    for (int x = 0; x < count && !seen; ++x) seen = elements[x] == candidate;
                    if (!seen && count < FIT_MAX) elements[count++] = candidate;
                }
            }
        }
        double weight[FIT_MAX];
        int n = fit_weights(mesh, (uint32_t)v, elements, count, weight);
        if (n == 0) continue; /* a strip one element wide: keep the average */
        if (used + (size_t)n > capacity) {
            size_t grown = 2 * capacity + (size_t)n;
            uint32_t *e = rad_realloc(ctx, r->fit_element, grown, sizeof *e);
            if (e) r->fit_element = e;
            double *w = e ? rad_realloc(ctx, r->fit_weight, grown, sizeof *w) : NULL;
            if (w) r->fit_weight = w;
            if (!e || !w) {
                status = RAD_ERROR_NO_MEMORY;
                break;
            }
            capacity = grown;
        }
        r->fit_vertex[fit] = (uint32_t)v;
        r->fit_first[fit] = (uint32_t)used;
        r->fit_size[fit] = (uint32_t)n;
        for (int i = 0; i < n; ++i) {
            r->fit_element[used + (size_t)i] = elements[i];
            r->fit_weight[used + (size_t)i] = weight[i];
        }
        used += (size_t)n;
        ++fit;
    }
    r->fit_count = fit;
    rad_free(ctx, boundary);
    rad_free(ctx, around.first);
    rad_free(ctx, around.element);
    return status;
}

/* Boundary vertices: the fitted plane's value of the per-element values, kept between half the
 * smallest and one and a half times the largest value it was fitted to, so a shadow edge cannot
 * throw it far. */
static void fit_boundary(const rad_renderer *r, float (*element_value)[3],
                         float (*vertex_value)[3]) {
    for (size_t i = 0; i < r->fit_count; ++i) {
        const uint32_t *elements = r->fit_element + r->fit_first[i];
        const double *weight = r->fit_weight + r->fit_first[i];
        for (int c = 0; c < 3; ++c) {
            double value = 0, lo = INFINITY, hi = 0;
            for (uint32_t k = 0; k < r->fit_size[i]; ++k) {
                double b = element_value[elements[k]][c];
                value += weight[k] * b;
                lo = fmin(lo, b);
                hi = fmax(hi, b);
            }
            vertex_value[r->fit_vertex[i]][c] = (float)fmin(fmax(value, 0.5 * lo), 1.5 * hi);
        }
    }
}

/* The light an element emits beyond its material's own: the specular-first deposit
 * (docs/specular-first.md), E / pi - L_material, at least 0. */
static void element_deposit(const rad_renderer *r, size_t e, float out[3]) {
    const double *own = rad_renderer_material(r, (uint32_t)e)->emission;
    for (int c = 0; c < 3; ++c) out[c] = fmaxf(0.0f, r->element_emission[e][c] - (float)own[c]);
}

/* Each element's corners from the smoothed vertex values, scaled so the mean over the element
 * stays its own value (the corner mean is the mean of the bilinear or barycentric
 * interpolation over the element); where the scale would pass MAX_MEAN_SCALE (a lone bright
 * element), the element keeps its value flat. */
#define MAX_MEAN_SCALE 4.0f

static void mean_keeping_corners(const rad_renderer *r, float (*element_value)[3],
                                 float (*vertex_value)[3], float (*corners_out)[4][3]) {
    const rad_mesh *mesh = r->mesh;
    for (size_t e = 0; e < mesh->element_count; ++e) {
        int corners = rad_mesh_corner_count(mesh, e);
        for (int c = 0; c < 3; ++c) {
            float mean = 0;
            for (int k = 0; k < corners; ++k) mean += vertex_value[mesh->element_vertices[e][k]][c];
            mean /= (float)corners;
            int flat = !(mean > 0) || element_value[e][c] > MAX_MEAN_SCALE * mean;
            for (int k = 0; k < corners; ++k)
                corners_out[e][k][c] =
                    flat ? element_value[e][c]
                         : vertex_value[mesh->element_vertices[e][k]][c] * (element_value[e][c] / mean);
        }
    }
}

/* The deposit is one value per element, often sharp (a caustic, the patch of light a sphere
 * throws on the ceiling): shown flat it draws the element grid. It is smoothed as the
 * radiosity is (area-weighted means at the vertices, the fitted plane on boundaries), then each
 * element's corners are scaled so the mean over the element stays its own deposit: smoothing
 * must not move light from a bright element into dark neighbours (a caustic narrower than the
 * elements would spread over three times its size): mean_keeping_corners. */

static rad_status deposit_prepare(rad_renderer *r) {
    const rad_mesh *mesh = r->mesh;
    int any = 0;
    for (size_t e = 0; e < mesh->element_count && !any; ++e) {
        float d[3];
        element_deposit(r, e, d);
        any = d[0] > 0 || d[1] > 0 || d[2] > 0;
    }
    rad_free(r->ctx, r->corner_deposit);
    r->corner_deposit = NULL;
    if (!any) return RAD_OK;
    float(*deposit)[3] = rad_alloc(r->ctx, mesh->element_count + 1, sizeof *deposit);
    double *weight = rad_alloc_zero(r->ctx, mesh->vertex_count + 1, sizeof *weight);
    float(*vertex)[3] = rad_alloc_zero(r->ctx, mesh->vertex_count + 1, sizeof *vertex);
    r->corner_deposit = rad_alloc_zero(r->ctx, mesh->element_count + 1, sizeof *r->corner_deposit);
    rad_status status = deposit && weight && vertex && r->corner_deposit ? RAD_OK : RAD_ERROR_NO_MEMORY;
    for (size_t e = 0; e < mesh->element_count && !status; ++e) {
        element_deposit(r, e, deposit[e]);
        for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
            uint32_t v = mesh->element_vertices[e][k];
            weight[v] += mesh->element_area[e];
            for (int c = 0; c < 3; ++c) vertex[v][c] += (float)(mesh->element_area[e] * deposit[e][c]);
        }
    }
    for (size_t v = 0; v < mesh->vertex_count && !status; ++v)
        for (int c = 0; c < 3; ++c) vertex[v][c] = weight[v] > 0 ? (float)(vertex[v][c] / weight[v]) : 0;
    if (!status) fit_boundary(r, deposit, vertex);
    if (!status) mean_keeping_corners(r, deposit, vertex, r->corner_deposit);
    rad_free(r->ctx, deposit);
    rad_free(r->ctx, weight);
    rad_free(r->ctx, vertex);
    return status;
}

/* The smooth bare picture (collocate.c): what each element holds besides the light evaluated at
 * its corners (its emission, and whatever the evaluations miss) is averaged at the vertices
 * (and fitted on boundaries) as the radiosity is; each corner adds the light evaluated just
 * inside it. The evaluations use the same rays at every point, so their errors mostly cancel in
 * the difference between a corner and the centroids around it. */
static rad_status collocated_prepare(rad_renderer *r) {
    rad_context *ctx = r->ctx;
    const rad_mesh *mesh = r->mesh;
    size_t n = mesh->element_count;
    float(*rest)[3] = rad_alloc(ctx, n + 1, sizeof *rest);
    float(*vertex)[3] = rad_alloc(ctx, mesh->vertex_count + 1, sizeof *vertex);
    double *weight = rad_alloc_zero(ctx, mesh->vertex_count + 1, sizeof *weight);
    double(*sum)[3] = rad_alloc_zero(ctx, mesh->vertex_count + 1, sizeof *sum);
    r->corner_collocated = rad_alloc(ctx, n + 1, sizeof *r->corner_collocated);
    rad_status status = rest && vertex && weight && sum && r->corner_collocated ? RAD_OK : RAD_ERROR_NO_MEMORY;
    if (!status) status = rad_collocate_light(r, r->corner_collocated);
    if (!status) {
        for (size_t e = 0; e < n; ++e) {
            /* What the corners' light leaves of the element's value: the mean of its corners (the
             * mean of the picture drawn over it, as it interpolates them) and not the light at its
             * centroid, so the element shows its own value whatever the light does inside it (a
             * hierarchy's large leaf at a shadow's edge). Cornell, 256 x 256, 8x8 blocks: the
             * default bare render 2.47% -> 1.86%, the hierarchy's at link error 1e-4 12.5% ->
             * 11.0% (docs/hierarchical.md). */
            int corners = rad_mesh_corner_count(mesh, e);
            for (int c = 0; c < 3; ++c) {
                double mean = 0;
                for (int k = 0; k < corners; ++k) mean += r->corner_collocated[e][k][c];
                rest[e][c] = r->element_radiance[e][c] - (float)(mean / corners);
            }
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k) {
                uint32_t v = mesh->element_vertices[e][k];
                weight[v] += mesh->element_area[e];
                for (int c = 0; c < 3; ++c) sum[v][c] += mesh->element_area[e] * rest[e][c];
            }
        }
        for (size_t v = 0; v < mesh->vertex_count; ++v)
            for (int c = 0; c < 3; ++c) vertex[v][c] = weight[v] > 0 ? (float)(sum[v][c] / weight[v]) : 0;
        fit_boundary(r, rest, vertex);
        for (size_t e = 0; e < n; ++e)
            for (int k = 0; k < rad_mesh_corner_count(mesh, e); ++k)
                for (int c = 0; c < 3; ++c) {
                    float *value = &r->corner_collocated[e][k][c];
                    *value = fmaxf(0.0f, vertex[mesh->element_vertices[e][k]][c] + *value);
                }
    }
    rad_free(ctx, rest);
    rad_free(ctx, vertex);
    rad_free(ctx, weight);
    rad_free(ctx, sum);
    if (status) {
        rad_free(ctx, r->corner_collocated);
        r->corner_collocated = NULL;
    }
    return status;
}

rad_status rad_reconstruct_prepare(rad_renderer *r) {
    const rad_solution_view *solution = r->solution;
    const rad_mesh *mesh = r->mesh;
    rad_context *ctx = r->ctx;
    rad_rgb *vertex = rad_alloc(ctx, mesh->vertex_count ? mesh->vertex_count : 1, sizeof *vertex);
    if (!vertex) return RAD_ERROR_NO_MEMORY;
    rad_status status = rad_solution_vertex_radiosity(solution, ctx, r->settings.ambient, vertex);
    if (status) {
        rad_free(ctx, vertex);
        return status;
    }
    const float to_radiance = (float)(1 / RAD_PI);
    for (size_t v = 0; v < mesh->vertex_count; ++v)
        for (int c = 0; c < 3; ++c) r->vertex_radiance[v][c] = (float)vertex[v][c] * to_radiance;
    rad_free(ctx, vertex);
    for (size_t e = 0; e < mesh->element_count; ++e) {
        double b[3], emission[3], reflectance[3];
        /* Flat shading shows the leaf's value at its centre. */
        double centre = rad_solution_leaf_centre(mesh, e);
        rad_solution_display_radiosity(solution, e, centre, centre, r->settings.ambient, b);
        solution->ops->emission(solution, e, emission);
        solution->ops->reflectance(solution, e, reflectance);
        for (int c = 0; c < 3; ++c) {
            r->element_radiance[e][c] = (float)b[c] * to_radiance;
            r->element_emission[e][c] = (float)emission[c] * to_radiance;
            r->element_reflectance[e][c] = (float)reflectance[c];
        }
    }
    fit_boundary(r, r->element_radiance, r->vertex_radiance);
    /* What gather rays read: smooth, but no element's light moved into its neighbours. Plain
     * vertex averages lose light where the radiosity peaks inside a surface (a wall's middle):
     * seen from the ceiling, lit only by the solution, the Cornell box's walls and floor were
     * 0.9% too dark at 2,634 elements, 0.33% with flat values (docs/rendering.md). */
    rad_free(ctx, r->corner_radiance);
    r->corner_radiance = rad_alloc(ctx, mesh->element_count + 1, sizeof *r->corner_radiance);
    if (!r->corner_radiance) return RAD_ERROR_NO_MEMORY;
    mean_keeping_corners(r, r->element_radiance, r->vertex_radiance, r->corner_radiance);
    status = deposit_prepare(r);
    /* The smooth bare picture: the light evaluated at the corners (collocate.c). */
    rad_free(ctx, r->corner_collocated);
    r->corner_collocated = NULL;
    if (!status && rad_collocate_wanted(r)) status = collocated_prepare(r);
    return status;
}

/* The element's value at (u, v) interpolated from its corners' (corner k, channel c at
 * corner[3 k + c]; flat shading: its own). */
static void interpolate(const rad_renderer *r, uint32_t element, double u, double v,
                        const float *corner, double out[3]) {
    if (r->settings.shading == RAD_SHADING_FLAT) {
        for (int c = 0; c < 3; ++c) out[c] = r->element_radiance[element][c];
        return;
    }
    double weight[4];
    int corners = rad_element_weights(r->mesh, element, u, v, weight);
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < corners; ++k)
        for (int c = 0; c < 3; ++c) out[c] += weight[k] * corner[3 * k + c];
}

void rad_reconstruct_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]) {
    if (r->corner_collocated) {
        interpolate(r, element, u, v, &r->corner_collocated[element][0][0], out);
        return;
    }
    float corner[4][3];
    for (int k = 0; k < rad_mesh_corner_count(r->mesh, element); ++k)
        memcpy(corner[k], r->vertex_radiance[r->mesh->element_vertices[element][k]], sizeof corner[k]);
    interpolate(r, element, u, v, &corner[0][0], out);
}

void rad_reconstruct_gather_radiance(const rad_renderer *r, uint32_t element, double u, double v,
                                     double out[3]) {
    interpolate(r, element, u, v, &r->corner_radiance[element][0][0], out);
}

void rad_reconstruct_emission(const rad_renderer *r, uint32_t element, double u, double v,
                              double out[3]) {
    if (r->settings.shading == RAD_SHADING_FLAT || !r->corner_deposit) {
        for (int c = 0; c < 3; ++c) out[c] = r->element_emission[element][c];
        return;
    }
    const double *own = rad_renderer_material(r, element)->emission;
    double weight[4];
    int corners = rad_element_weights(r->mesh, element, u, v, weight);
    for (int c = 0; c < 3; ++c) out[c] = fmin(own[c], r->element_emission[element][c]);
    for (int k = 0; k < corners; ++k)
        for (int c = 0; c < 3; ++c) out[c] += weight[k] * r->corner_deposit[element][k][c];
}
