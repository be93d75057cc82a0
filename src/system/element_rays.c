/* element_rays.c - Embree scene of the element mesh (see element_rays.h). */
#include "system/element_rays.h"

#include "scene/rays.h"

#include <float.h>
#include <stdio.h>
#include <string.h>

void rad_element_rays_destroy(rad_element_rays *rays) {
    if (!rays) return;
    if (rays->scene) rtcReleaseScene(rays->scene);
    if (rays->device) rtcReleaseDevice(rays->device);
    rad_free(rays->ctx, rays->quads);
    rad_free(rays->ctx, rays->loose);
    rad_free(rays->ctx, rays->cells);
    rad_free(rays->ctx, rays);
}

/* One Embree quad geometry holding every element: a triangle (v0, v1, v2) goes in as the quad
 * (v0, v1, v2, v2), which Embree documents as the way to mix the two; its hits all fall in the
 * quad's first half (v0, v1, v3), where u and v are the triangle's own. One geometry rather than
 * a quad and a triangle geometry: one BVH to traverse (less processor time on the Cornell render
 * and on Sponza, the same hits on the Cornell box: docs/rendering.md, "One element geometry").
 *
 * Flat convex grids and trees go in as one quad (or triangle) each, before the other elements
 * (rad_grid_quad): the fewer primitives, the shallower Embree's tree and the fewer boxes a ray
 * enters. A shape is taken when its corners lie within SHAPE_FLAT epsilons of one plane (its
 * elements then lie in it too: a bilinear map of a flat quad is flat, and so are its
 * subdivisions), it turns the same way at every corner, and (a grid) it holds more than one
 * element. */
#define SHAPE_FLAT 1e-3

static double cross2(const double a[2], const double b[2]) { return a[0] * b[1] - a[1] * b[0]; }

/* The shape with corners c (3 or 4, counter-clockwise) as a quad, or 0 when it is not flat and
 * convex. */
static int shape_make(const rad_vec3 *c, int count, double epsilon, rad_grid_quad *out) {
    rad_vec3 normal = count == 4 ? v3_cross(v3_sub(c[2], c[0]), v3_sub(c[3], c[1]))
                                 : v3_cross(v3_sub(c[1], c[0]), v3_sub(c[2], c[0]));
    if (!(v3_length(normal) > 0)) return 0;
    normal = v3_normalize(normal);
    rad_vec3 centre = v3(0, 0, 0);
    for (int k = 0; k < count; ++k) centre = v3_add(centre, v3_scale(c[k], 1.0 / count));
    for (int k = 0; k < count; ++k) {
        if (!(fabs(v3_dot(normal, v3_sub(c[k], centre))) <= SHAPE_FLAT * epsilon)) return 0;
        rad_vec3 in = v3_sub(c[k], c[(k + count - 1) % count]);
        rad_vec3 next = v3_sub(c[(k + 1) % count], c[k]);
        if (!(v3_dot(v3_cross(in, next), normal) > 0)) return 0;
    }
    rad_vec3 axis_x = v3_normalize(v3_sub(c[1], c[0])), axis_y = v3_cross(normal, axis_x);
    double p[4][2];
    for (int k = 0; k < count; ++k) {
        rad_vec3 d = v3_sub(c[k], c[0]);
        p[k][0] = v3_dot(d, axis_x);
        p[k][1] = v3_dot(d, axis_y);
    }
    if (count == 3) { /* Embree's quad (c0, c1, c2, c2): u, v the triangle's own */
        p[3][0] = p[2][0];
        p[3][1] = p[2][1];
    }
    for (int a = 0; a < 2; ++a) {
        out->e[a] = p[1][a];
        out->f[a] = p[3][a];
        out->c2[a] = p[2][a];
        out->g[a] = p[2][a] - p[1][a] - p[3][a];
    }
    out->ef = cross2(out->e, out->f);
    out->gf = cross2(out->g, out->f);
    /* A parallelogram, to rounding: Embree's u, v on the quad are its own bilinear s, t. */
    double size = fabs(out->e[0]) + fabs(out->e[1]) + fabs(out->f[0]) + fabs(out->f[1]);
    out->affine = fabs(out->g[0]) + fabs(out->g[1]) <= 1e-9 * size;
    out->nearly_affine = fabs(out->gf) <= 1e-4 * fabs(out->ef);
    out->half_inverse_gf = out->gf != 0 ? 0.5 / out->gf : 0;
    out->triangle = count == 3;
    out->origin = c[0];
    out->axis_x = axis_x;
    out->axis_y = axis_y;
    out->grid = NULL;
    out->tree = NULL;
    out->table_depth = 0;
    out->table = 0;
    return 1;
}

/* The point of Embree's hit at (u, v) of the quad, in its plane's frame: Embree's triangles
 * (0, 1, 3) and (2, 3, 1) of the quad (for a triangle the first only). */
static void shape_point(const rad_grid_quad *q, double u, double v, double h[2]) {
    for (int a = 0; a < 2; ++a)
        h[a] = q->triangle || u + v <= 1
                   ? u * q->e[a] + v * q->f[a]
                   : q->c2[a] + (1 - u) * (q->f[a] - q->c2[a]) + (1 - v) * (q->e[a] - q->c2[a]);
}

/* The coordinates s, t of Embree's hit at (u, v) in the quad's bilinear map; on a triangle, the
 * barycentric coordinates (Embree's own). */
static void shape_coordinates(const rad_grid_quad *q, double u, double v, double *s_out,
                              double *t_out) {
    if (q->affine || q->triangle) {
        *s_out = u;
        *t_out = v;
        return;
    }
    double h[2];
    shape_point(q, u, v, h);
    /* h = s e + t f + s t g: h - t f is parallel to e + t g, so
     * cross(h, e) + t (cross(h, g) + cross(e, f)) + t^2 cross(g, f) = 0. */
    double k0 = cross2(h, q->e), k1 = cross2(h, q->g) + q->ef, k2 = q->gf, t;
    if (q->nearly_affine) {
        /* k2 small against k1: the linear root and two corrections, error O((k2 / k1)^3). */
        double inverse = 1 / k1;
        t = -k0 * inverse;
        t = -(k0 + k2 * t * t) * inverse;
        t = -(k0 + k2 * t * t) * inverse;
    } else {
        /* The root in [0, 1] (the other lies outside a convex quad). */
        double w = k1 * k1 - 4 * k0 * k2;
        w = sqrt(w > 0 ? w : 0);
        double t1 = (-k1 - w) * q->half_inverse_gf, t2 = (-k1 + w) * q->half_inverse_gf;
        double off1 = t1 < 0 ? -t1 : t1 > 1 ? t1 - 1 : 0;
        double off2 = t2 < 0 ? -t2 : t2 > 1 ? t2 - 1 : 0;
        t = off1 <= off2 ? t1 : t2;
    }
    double along[2] = {q->e[0] + t * q->g[0], q->e[1] + t * q->g[1]};
    *s_out = ((h[0] - t * q->f[0]) * along[0] + (h[1] - t * q->f[1]) * along[1]) /
             (along[0] * along[0] + along[1] * along[1]);
    *t_out = t;
}

static double unit_clamp(double x) { return !(x > 0) ? 0 : x > 1 ? 1 : x; }

/* Where on a grid's element Embree's hit of the grid's quad at (u, v) is: the element, and the
 * point's coordinates in the element's own bilinear map (the grid's cell (s nu - i, t nv - j),
 * s, t the point's coordinates in the grid's map). On a parallelogram those are Embree's u, v
 * of the element's two triangles (rad_element_point); on another flat quad (the Cornell floor's
 * pieces beside the rotated blocks) they differ from them as the quad from a parallelogram: a
 * parametrisation as good for interpolating the element's corners, continuous from one element
 * to the next. Rounding (or a degenerate quad's NaN) is clamped into the grid. */
static void grid_locate(const rad_grid_quad *q, double u, double v, rad_element_hit *hit) {
    double s, t;
    shape_coordinates(q, u, v, &s, &t);
    const rad_mesh_grid *g = q->grid;
    double si = s * g->nu, tj = t * g->nv;
    uint32_t i = !(si > 0) ? 0 : si >= g->nu - 1 ? g->nu - 1 : (uint32_t)si;
    uint32_t j = !(tj > 0) ? 0 : tj >= g->nv - 1 ? g->nv - 1 : (uint32_t)tj;
    hit->element = rad_mesh_grid_element(g, i, j);
    hit->u = unit_clamp(si - i);
    hit->v = unit_clamp(tj - j);
}

/* Point x in the shape's plane frame, less h. */
static inline void project(rad_vec3 x, const rad_grid_quad *q, const double h[2], double out[2]) {
    rad_vec3 d = v3_sub(x, q->origin);
    out[0] = v3_dot(d, q->axis_x) - h[0];
    out[1] = v3_dot(d, q->axis_y) - h[1];
}

/* One level down a tree from `node` (split) at coordinates (s, t) in it: the child that holds
 * the point (mesh.h's order), and (s, t) made the child's own. */
static inline uint32_t descend(const rad_mesh_tree_node *nodes, uint32_t node, int triangle,
                               double *s_io, double *t_io) {
    uint32_t first = nodes[node].first;
    double s = *s_io, t = *t_io;
    if (!triangle) {
        int a = s >= 0.5, b = t >= 0.5;
        *s_io = 2 * s - a;
        *t_io = 2 * t - b;
        return first + (uint32_t)(b ? 3 - a : a);
    }
    if (s >= 0.5) {
        *s_io = 2 * s - 1;
        *t_io = 2 * t;
        return first + 1;
    }
    if (t >= 0.5) {
        *s_io = 2 * s;
        *t_io = 2 * t - 1;
        return first + 2;
    }
    if (s + t <= 0.5) {
        *s_io = 2 * s;
        *t_io = 2 * t;
        return first;
    }
    *s_io = 1 - 2 * s;
    *t_io = 1 - 2 * t;
    return first + 3;
}

/* The cell at depth `depth` below a root that holds the point (s, t) of the root (bilinear on a
 * quad, barycentric on a triangle), its index in the root's table, and the point's coordinates
 * in it. A quad's cells are the 4^depth squares of side 2^-depth, row by row; a triangle's are
 * the regular grid's triangles, two to a square (i, j), the second (i + j < n - 1) the upper,
 * inverted one, whose corners 0, 1, 2 lie at (i + 1, j + 1), (i, j + 1), (i + 1, j): every
 * node at that depth is one of them, so made (mesh.h). Rounding is clamped into the root. */
static size_t tree_cell(int triangle, int depth, double s, double t, double *s_out,
                        double *t_out) {
    int64_t n = (int64_t)1 << depth;
    double x = s * (double)n, y = t * (double)n;
    int64_t i = !(x > 0) ? 0 : x >= (double)(n - 1) ? n - 1 : (int64_t)x;
    int64_t j = !(y > 0) ? 0 : y >= (double)(n - 1) ? n - 1 : (int64_t)y;
    if (!triangle) {
        *s_out = unit_clamp(x - (double)i);
        *t_out = unit_clamp(y - (double)j);
        return (size_t)(j * n + i);
    }
    if (i + j > n - 1) i = n - 1 - j;
    int up = (x - (double)i) + (y - (double)j) > 1 && i + j < n - 1;
    *s_out = unit_clamp(up ? (double)(i + 1) - x : x - (double)i);
    *t_out = unit_clamp(up ? (double)(j + 1) - y : y - (double)j);
    return (size_t)((j * n + i) * 2 + up);
}

/* The same on a tree (mesh.h): the root's table gives the node at its depth that holds the
 * point (or the leaf above it), then down by the point's coordinates, halved at each split; at
 * a leaf drawn as itself its coordinates are the element's (bilinear on a quad, barycentric on
 * a triangle), on a fan the triangle about the leaf's centre that holds the point. */
static void tree_locate(const rad_element_rays *rays, const rad_grid_quad *q, double u, double v,
                        rad_element_hit *hit) {
    const rad_mesh *mesh = rays->mesh;
    const rad_mesh_tree_node *nodes = mesh->tree_nodes;
    double s, t;
    shape_coordinates(q, u, v, &s, &t);
    uint32_t node = q->tree->node;
    const rad_mesh_tree_node *leaf = NULL;
    if (q->table_depth > 0) {
        double s0 = s, t0 = t;
        const rad_tree_cell *cell =
            &rays->cells[q->table + tree_cell(q->triangle, q->table_depth, s0, t0, &s, &t)];
        node = cell->node;
        if (cell->depth < (uint32_t)q->table_depth)
            tree_cell(q->triangle, (int)cell->depth, s0, t0, &s, &t);
        if (cell->leaf.count) leaf = &cell->leaf; /* no load of the node */
    }
    if (!leaf) {
        for (int depth = 0; nodes[node].count == 0 && depth < 256; ++depth)
            node = descend(nodes, node, q->triangle, &s, &t);
        leaf = &nodes[node];
    }
    hit->element = leaf->first;
    hit->u = unit_clamp(s);
    hit->v = unit_clamp(t);
    if (leaf->count <= 1) return;
    /* A fan: triangle k is (centre, a_k, a_k+1) with a_k along the outline in order, so the
     * point lies in the sector between centre -> a_k and centre -> a_k+1: one projection a
     * triangle, the barycentric coordinates only for the triangle taken (the first sector that
     * holds the point, or against rounding the one it is least outside). */
    double h[2];
    shape_point(q, u, v, h);
    const uint32_t *first = mesh->element_vertices[leaf->first];
    double centre[2], a[2], b[2];
    project(mesh->vertices[first[0]], q, h, centre);
    project(mesh->vertices[first[1]], q, h, a);
    a[0] -= centre[0], a[1] -= centre[1];
    /* The point less the centre is -centre. */
    double x[2] = {-centre[0], -centre[1]}, best = -INFINITY;
    uint32_t take = 0;
    for (uint32_t k = 0; k < leaf->count; ++k) {
        project(mesh->vertices[mesh->element_vertices[leaf->first + k][2]], q, h, b);
        b[0] -= centre[0], b[1] -= centre[1];
        double from = cross2(a, x), to = cross2(x, b);
        double inside = from < to ? from : to;
        if (inside >= 0) {
            take = k;
            break;
        }
        if (inside > best) best = inside, take = k;
        a[0] = b[0], a[1] = b[1];
    }
    const uint32_t *c = mesh->element_vertices[leaf->first + take];
    double p[3][2];
    for (int i = 0; i < 3; ++i) project(mesh->vertices[c[i]], q, h, p[i]);
    /* 0 = p0 + a (p1 - p0) + b (p2 - p0), the p less the point. */
    double e1[2] = {p[1][0] - p[0][0], p[1][1] - p[0][1]};
    double e2[2] = {p[2][0] - p[0][0], p[2][1] - p[0][1]};
    double det = cross2(e1, e2);
    hit->element = leaf->first + take;
    hit->u = det != 0 ? unit_clamp(cross2(e2, p[0]) / det) : 0;
    hit->v = det != 0 ? unit_clamp(cross2(p[0], e1) / det) : 0;
}

/* The element and u, v of Embree's hit of primitive `primitive` at (u, v). */
static inline void hit_element(const rad_element_rays *rays, unsigned primitive, float u, float v,
                               rad_element_hit *hit) {
    if (primitive < rays->quad_count) {
        const rad_grid_quad *q = &rays->quads[primitive];
        if (q->grid) grid_locate(q, u, v, hit);
        else tree_locate(rays, q, u, v, hit);
        return;
    }
    hit->element = rays->loose ? rays->loose[primitive - rays->quad_count] : primitive;
    hit->u = u;
    hit->v = v;
}

/* Marks the elements under tree node `node`; returns its leaves. */
static size_t mark_tree(const rad_mesh *mesh, uint32_t node, int depth, uint8_t *covered) {
    const rad_mesh_tree_node *n = &mesh->tree_nodes[node];
    size_t leaves = 0;
    if (n->count == 0) {
        if (depth < 256)
            for (uint32_t k = 0; k < 4; ++k)
                leaves += mark_tree(mesh, n->first + k, depth + 1, covered);
        return leaves;
    }
    for (uint32_t k = 0; k < n->count; ++k) covered[n->first + k] = 1;
    return 1;
}

/* Cells of a root's table (tree_locate): at the deepest depth where they number no more than
 * its leaves, at most TABLE_DEPTH (a quad's 4^depth cells, a triangle's twice that): 16 or 32
 * bytes a leaf at most. */
#define TABLE_DEPTH 9

static int table_depth(size_t leaves) {
    int depth = 0;
    while (depth < TABLE_DEPTH && ((size_t)1 << (2 * (depth + 1))) <= leaves) ++depth;
    return depth;
}

/* Fills a root's table: each cell's node at the table's depth, or the leaf above it. */
static void table_fill(const rad_mesh *mesh, const rad_grid_quad *q, rad_tree_cell *cells) {
    int depth = q->table_depth;
    size_t n = (size_t)1 << depth;
    for (size_t j = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i)
            for (int up = 0; up < (q->triangle ? 2 : 1); ++up) {
                if (q->triangle && i + j + (size_t)up > n - 1) continue;
                /* The cell's centre: a square's middle, a triangle's centroid. */
                double inside = !q->triangle ? 0.5 : up ? 2.0 / 3 : 1.0 / 3;
                double s = ((double)i + inside) / (double)n, t = ((double)j + inside) / (double)n;
                double ls, lt;
                size_t index = tree_cell(q->triangle, depth, s, t, &ls, &lt);
                uint32_t node = q->tree->node, d = 0;
                while (d < (uint32_t)depth && mesh->tree_nodes[node].count == 0) {
                    node = descend(mesh->tree_nodes, node, q->triangle, &s, &t);
                    ++d;
                }
                cells[index] = (rad_tree_cell){node, d, mesh->tree_nodes[node]};
            }
}

/* The shapes Embree traces whole (the flat grids and trees), and which elements they cover. */
static rad_status shapes_make(rad_element_rays *rays, uint8_t **covered_out) {
    const rad_mesh *mesh = rays->mesh;
    size_t shapes = mesh->grid_count + mesh->tree_count;
    *covered_out = NULL;
    if (!shapes) return RAD_OK;
    rays->quads = rad_alloc(rays->ctx, shapes, sizeof *rays->quads);
    uint8_t *covered = rad_alloc_zero(rays->ctx, mesh->element_count, sizeof *covered);
    if (!rays->quads || !covered) {
        rad_free(rays->ctx, covered);
        return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "out of memory for %zu shapes", shapes);
    }
    for (size_t g = 0; g < mesh->grid_count; ++g) {
        const rad_mesh_grid *grid = &mesh->grids[g];
        rad_grid_quad *quad = &rays->quads[rays->quad_count];
        rad_vec3 c[4];
        for (int k = 0; k < 4; ++k) c[k] = mesh->vertices[grid->corner[k]];
        if ((uint64_t)grid->nu * grid->nv < 2 || !shape_make(c, 4, rays->epsilon, quad)) continue;
        quad->grid = grid;
        rays->quad_count++;
        memset(covered + grid->first, 1, (size_t)grid->nu * grid->nv);
    }
    size_t cell_count = 0;
    for (size_t i = 0; i < mesh->tree_count; ++i) {
        const rad_mesh_tree *tree = &mesh->trees[i];
        rad_grid_quad *quad = &rays->quads[rays->quad_count];
        if (!shape_make(tree->corner, (int)tree->corner_count, rays->epsilon, quad)) continue;
        quad->tree = tree;
        rays->quad_count++;
        quad->table_depth = table_depth(mark_tree(mesh, tree->node, 0, covered));
        quad->table = cell_count;
        if (quad->table_depth > 0)
            cell_count += ((size_t)1 << (2 * quad->table_depth)) * (quad->triangle ? 2 : 1);
    }
    *covered_out = covered;
    if (!cell_count) return RAD_OK;
    /* Without room for the tables, hits walk down from the roots. */
    rays->cells = rad_alloc(rays->ctx, cell_count, sizeof *rays->cells);
    for (size_t q = 0; q < rays->quad_count && !rays->cells; ++q) rays->quads[q].table_depth = 0;
    for (size_t q = 0; q < rays->quad_count && rays->cells; ++q)
        if (!rays->quads[q].grid && rays->quads[q].table_depth > 0)
            table_fill(mesh, &rays->quads[q], rays->cells + rays->quads[q].table);
    return RAD_OK;
}

static rad_status add_elements(rad_element_rays *rays) {
    const rad_mesh *mesh = rays->mesh;
    if (mesh->element_count == 0) return RAD_OK;
    uint8_t *covered = NULL;
    rad_status status = shapes_make(rays, &covered);
    if (status) return status;
    size_t loose = 0;
    for (size_t e = 0; e < mesh->element_count; ++e) loose += !covered || !covered[e];
    size_t primitives = rays->quad_count + loose, trees = 0;
    rays->loose_count = loose;
    for (size_t q = 0; q < rays->quad_count; ++q) trees += rays->quads[q].grid == NULL;
    if (rays->quad_count) {
        rays->loose = rad_alloc(rays->ctx, loose + 1, sizeof *rays->loose);
        if (!rays->loose) {
            rad_free(rays->ctx, covered);
            return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "out of memory for %zu elements",
                            mesh->element_count);
        }
    }
    RTCGeometry geometry = rtcNewGeometry(rays->device, RTC_GEOMETRY_TYPE_QUAD);
    /* The mesh's vertices, then each tree's corners (a tree's root is no element). */
    float *positions = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                               mesh->vertex_count + 4 * trees);
    unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                                                RTC_FORMAT_UINT4, 4 * sizeof(unsigned),
                                                primitives);
    if (!positions || !indices) {
        rtcReleaseGeometry(geometry);
        rad_free(rays->ctx, covered);
        return rad_fail(rays->ctx, RAD_ERROR_NO_MEMORY, "Embree: out of memory for %zu elements",
                        mesh->element_count);
    }
    for (size_t i = 0; i < mesh->vertex_count; ++i)
        rad_ray_frame_point(&rays->frame, mesh->vertices[i], positions + 3 * i);
    size_t at = 0, extra = mesh->vertex_count;
    for (size_t q = 0; q < rays->quad_count; ++q, ++at) {
        const rad_grid_quad *quad = &rays->quads[q];
        if (quad->grid) {
            for (int k = 0; k < 4; ++k) indices[4 * at + k] = quad->grid->corner[k];
            continue;
        }
        int count = (int)quad->tree->corner_count;
        for (int k = 0; k < 4; ++k) {
            rad_ray_frame_point(&rays->frame, quad->tree->corner[k < count ? k : count - 1],
                                positions + 3 * (extra + (size_t)k));
            indices[4 * at + k] = (unsigned)(extra + (size_t)k);
        }
        extra += 4;
    }
    for (size_t e = 0; e < mesh->element_count; ++e) {
        if (covered && covered[e]) continue;
        if (rays->loose) rays->loose[at - rays->quad_count] = (uint32_t)e;
        const uint32_t *c = mesh->element_vertices[e];
        int corners = rad_mesh_corner_count(mesh, e);
        for (int k = 0; k < 4; ++k) indices[4 * at + k] = c[k < corners ? k : corners - 1];
        ++at;
    }
    rad_free(rays->ctx, covered);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(rays->scene, geometry);
    rtcReleaseGeometry(geometry);
    return RAD_OK;
}

rad_status rad_element_rays_create(rad_context *ctx, const rad_mesh *mesh, rad_element_rays **out) {
    return rad_element_rays_create_with(ctx, mesh, 1, out);
}

rad_status rad_element_rays_create_with(rad_context *ctx, const rad_mesh *mesh, int robust,
                                          rad_element_rays **out) {
    *out = NULL;
    rad_element_rays *rays = rad_alloc_zero(ctx, 1, sizeof *rays);
    if (!rays) return RAD_ERROR_NO_MEMORY;
    rays->ctx = ctx;
    rays->mesh = mesh;
    rad_status status = rad_embree_open(ctx, &rays->device, &rays->scene);
    if (status) {
        rad_element_rays_destroy(rays);
        return status;
    }
    if (!robust) rtcSetSceneFlags(rays->scene, RTC_SCENE_FLAG_NONE);
    rad_vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < mesh->vertex_count; ++i) {
        rad_vec3 p = mesh->vertices[i];
        lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    rays->frame = rad_ray_frame_of_box(lo, hi);
    double diagonal = mesh->vertex_count ? v3_length(v3_sub(hi, lo)) : 1;
    /* Larger than float rounding in the frame, small against the scene's features. */
    rays->epsilon = diagonal * 1e-5;
    status = add_elements(rays);
    if (status) {
        rad_element_rays_destroy(rays);
        return status;
    }
    rtcCommitScene(rays->scene);
    if (rtcGetDeviceError(rays->device) != RTC_ERROR_NONE) {
        rad_element_rays_destroy(rays);
        return RAD_ERROR_INTERNAL;
    }
    *out = rays;
    return RAD_OK;
}

int rad_element_rays_intersect(const rad_element_rays *rays, rad_vec3 origin, rad_vec3 direction,
                               double tnear, double tfar, rad_element_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRayHit rh;
    double to_caller = rad_ray_frame_ray(&rays->frame, &rh.ray, origin, direction, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rays->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    hit->t = rh.ray.tfar * to_caller;
    hit_element(rays, rh.hit.primID, rh.hit.u, rh.hit.v, hit);
    /* Embree's Ng is (e1 x e2) for counter-clockwise corners: the front normal. */
    hit->front = (double)rh.hit.Ng_x * direction.x + (double)rh.hit.Ng_y * direction.y +
                     (double)rh.hit.Ng_z * direction.z < 0;
    return 1;
}

int rad_element_rays_occluded(const rad_element_rays *rays, rad_vec3 a, rad_vec3 b) {
    rad_vec3 d = v3_sub(b, a);
    double length = v3_length(d);
    if (length <= 2 * rays->epsilon) return 0;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRay ray;
    rad_ray_frame_ray(&rays->frame, &ray, a, d, rays->epsilon / length, 1 - rays->epsilon / length);
    rtcOccluded1(rays->scene, &context, &ray);
    return ray.tfar < 0;
}

void rad_element_rays_intersect16(const rad_element_rays *rays, rad_vec3 origin, const rad_vec3 *direction,
                                  int n, double tnear, rad_element_hit *hit) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTC_ALIGN(64) struct RTCRayHit16 rh;
    RTC_ALIGN(64) int valid[16];
    double to_caller[16];
    for (int i = 0; i < 16; ++i) {
        valid[i] = i < n ? -1 : 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        if (i < n)
            to_caller[i] = rad_ray_frame_lane(&rays->frame, &rh.ray, i, origin, direction[i], tnear, INFINITY);
        else
            rad_ray16_empty_lane(&rh.ray, i);
    }
    rtcIntersect16(valid, rays->scene, &context, &rh);
    for (int i = 0; i < n; ++i) {
        rad_element_hit *h = &hit[i];
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
            h->element = RAD_NO_ELEMENT;
            continue;
        }
        h->t = rh.ray.tfar[i] * to_caller[i];
        hit_element(rays, rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i], h);
        h->front = (double)rh.hit.Ng_x[i] * direction[i].x + (double)rh.hit.Ng_y[i] * direction[i].y +
                       (double)rh.hit.Ng_z[i] * direction[i].z < 0;
    }
}

void rad_element_rays_occluded16(const rad_element_rays *rays, rad_vec3 a, const rad_vec3 *b, int n,
                                 int *occluded) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTC_ALIGN(64) struct RTCRay16 ray;
    RTC_ALIGN(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
        rad_vec3 d = i < n ? v3_sub(b[i], a) : v3(0, 0, 0);
        double length = v3_length(d);
        valid[i] = i < n && length > 2 * rays->epsilon ? -1 : 0;
        if (valid[i])
            rad_ray_frame_lane(&rays->frame, &ray, i, a, d, rays->epsilon / length, 1 - rays->epsilon / length);
        else
            rad_ray16_empty_lane(&ray, i);
    }
    rtcOccluded16(valid, rays->scene, &context, &ray);
    for (int i = 0; i < n; ++i) occluded[i] = valid[i] && ray.tfar[i] < 0;
}

rad_vec3 rad_element_point(const rad_mesh *mesh, uint32_t element, double u, double v) {
    const uint32_t *c = mesh->element_vertices[element];
    const rad_vec3 *p = mesh->vertices;
    if (rad_mesh_corner_count(mesh, element) == 3)
        return v3_add(p[c[0]], v3_add(v3_scale(v3_sub(p[c[1]], p[c[0]]), u),
                                      v3_scale(v3_sub(p[c[2]], p[c[0]]), v)));
    /* Embree's two triangles: (v0, v1, v3) below the diagonal, (v2, v3, v1) above it. */
    if (u + v <= 1)
        return v3_add(p[c[0]], v3_add(v3_scale(v3_sub(p[c[1]], p[c[0]]), u),
                                      v3_scale(v3_sub(p[c[3]], p[c[0]]), v)));
    return v3_add(p[c[2]], v3_add(v3_scale(v3_sub(p[c[3]], p[c[2]]), 1 - u),
                                  v3_scale(v3_sub(p[c[1]], p[c[2]]), 1 - v)));
}
