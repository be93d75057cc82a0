/* generate_office.c - a lit open-plan office of about a given number of triangles, for
 * measuring solvers at scale: a grid of 3 m x 3 m cells under a 2.8 m ceiling, each with a
 * desk, a chair and a ceiling lamp (a housing whose bottom face emits), grouped four by four
 * into rooms by partition walls with a doorway in each, inside outer walls. Quads count as two
 * triangles. Deterministic: the same count gives the same file. */
#include "scene/scene.h"

#include <math.h>
#include <string.h>

#define CELL 3.0
#define HEIGHT 2.8
#define ROOM 4            /* cells per room side */
#define CELL_TRIANGLES 123 /* what one cell adds, walls shared out */

enum { FLOOR, CEILING, WALLS, DESKS, CHAIRS, HOUSINGS, LAMPS, SURFACES };

/* Box faces, bit k for: +x, -x, +y, -y, +z, -z. */
enum { PX = 1, NX = 2, PY = 4, NY = 8, PZ = 16, NZ = 32, SIDES = PX | NX | PZ | NZ };

static rad_status quad(rad_scene *s, uint32_t surface, rad_vec3 a, rad_vec3 b, rad_vec3 c,
                       rad_vec3 d) {
    rad_vec3 p[4] = {a, b, c, d};
    return rad_scene_add_polygon_points(s, surface, p, 4);
}

/* The faces of the box lo..hi named in `faces`, each facing out, counter-clockwise. */
static rad_status box(rad_scene *s, uint32_t surface, rad_vec3 lo, rad_vec3 hi, int faces,
                      uint32_t bottom_surface) {
    double x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
    rad_status st = RAD_OK;
    if (!st && (faces & PX)) st = quad(s, surface, v3(x1, y0, z0), v3(x1, y1, z0), v3(x1, y1, z1), v3(x1, y0, z1));
    if (!st && (faces & NX)) st = quad(s, surface, v3(x0, y0, z0), v3(x0, y0, z1), v3(x0, y1, z1), v3(x0, y1, z0));
    if (!st && (faces & PY)) st = quad(s, surface, v3(x0, y1, z0), v3(x0, y1, z1), v3(x1, y1, z1), v3(x1, y1, z0));
    if (!st && (faces & NY))
        st = quad(s, bottom_surface, v3(x0, y0, z0), v3(x1, y0, z0), v3(x1, y0, z1), v3(x0, y0, z1));
    if (!st && (faces & PZ)) st = quad(s, surface, v3(x0, y0, z1), v3(x1, y0, z1), v3(x1, y1, z1), v3(x0, y1, z1));
    if (!st && (faces & NZ)) st = quad(s, surface, v3(x0, y0, z0), v3(x0, y1, z0), v3(x1, y1, z0), v3(x1, y0, z0));
    return st;
}

/* Four legs of height h under a top spanning lo..hi in x and z (legs are open boxes). */
static rad_status legs(rad_scene *s, uint32_t surface, double x0, double z0, double x1, double z1,
                       double h, double t) {
    rad_status st = RAD_OK;
    const double xs[2] = {x0, x1 - t}, zs[2] = {z0, z1 - t};
    for (int i = 0; i < 2 && !st; ++i)
        for (int k = 0; k < 2 && !st; ++k)
            st = box(s, surface, v3(xs[i], 0, zs[k]), v3(xs[i] + t, h, zs[k] + t), SIDES, surface);
    return st;
}

/* One cell at (cx, cz): floor and ceiling tiles, desk, chair, lamp. */
static rad_status cell(rad_scene *s, const uint32_t *surf, int i, int k) {
    double x = i * CELL, z = k * CELL;
    rad_status st = quad(s, surf[FLOOR], v3(x, 0, z), v3(x, 0, z + CELL), v3(x + CELL, 0, z + CELL),
                         v3(x + CELL, 0, z));
    if (!st) st = quad(s, surf[CEILING], v3(x, HEIGHT, z), v3(x + CELL, HEIGHT, z),
                       v3(x + CELL, HEIGHT, z + CELL), v3(x, HEIGHT, z + CELL));
    /* Desk: a 1.6 x 0.8 m top at 0.72-0.75 m on four legs, turned every other cell. */
    int turn = (i + k) % 2;
    double dw = turn ? 0.8 : 1.6, dd = turn ? 1.6 : 0.8;
    double dx = x + 0.7, dz = z + 0.7;
    if (!st) st = box(s, surf[DESKS], v3(dx, 0.72, dz), v3(dx + dw, 0.75, dz + dd), 63, surf[DESKS]);
    if (!st) st = legs(s, surf[DESKS], dx, dz, dx + dw, dz + dd, 0.72, 0.05);
    /* Chair: a 0.45 m seat at 0.45 m, a back, four legs, in front of the desk. */
    double chx = turn ? dx + dw + 0.15 : dx + 0.55, chz = turn ? dz + 0.55 : dz + dd + 0.15;
    if (!st) st = box(s, surf[CHAIRS], v3(chx, 0.42, chz), v3(chx + 0.45, 0.47, chz + 0.45), 63, surf[CHAIRS]);
    if (!st) st = legs(s, surf[CHAIRS], chx, chz, chx + 0.45, chz + 0.45, 0.42, 0.03);
    if (!st) {
        rad_vec3 lo = turn ? v3(chx + 0.40, 0.47, chz) : v3(chx, 0.47, chz + 0.40);
        rad_vec3 hi = turn ? v3(chx + 0.45, 0.95, chz + 0.45) : v3(chx + 0.45, 0.95, chz + 0.45);
        st = box(s, surf[CHAIRS], lo, hi, 63 & ~NY, surf[CHAIRS]);
    }
    /* Lamp: a 0.6 x 0.6 m housing 0.08 m deep under the ceiling; its bottom face emits. */
    double lx = x + 1.2, lz = z + 1.2;
    if (!st) st = box(s, surf[HOUSINGS], v3(lx, HEIGHT - 0.08, lz), v3(lx + 0.6, HEIGHT, lz + 0.6),
                      SIDES | NY, surf[LAMPS]);
    return st;
}

/* A wall along a cell edge, from (x0, z0) to (x1, z1) (one of them constant), 0.1 m thick,
 * with both long faces and its ends. */
static rad_status wall(rad_scene *s, uint32_t surface, double x0, double z0, double x1, double z1) {
    double t = 0.05;
    rad_vec3 lo = x0 == x1 ? v3(x0 - t, 0, z0) : v3(x0, 0, z0 - t);
    rad_vec3 hi = x0 == x1 ? v3(x0 + t, HEIGHT, z1) : v3(x1, HEIGHT, z0 + t);
    return box(s, surface, lo, hi, SIDES, surface);
}

rad_status rad_scene_generate_office(rad_context *ctx, size_t triangles, rad_scene **out) {
    *out = NULL;
    if (triangles < CELL_TRIANGLES || triangles > 200000000)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "an office needs between %d and 200000000 triangles, not %zu",
                        CELL_TRIANGLES, triangles);
    size_t cells = triangles / CELL_TRIANGLES;
    int nx = (int)ceil(sqrt((double)cells)), nz = (int)((cells + (size_t)nx - 1) / (size_t)nx);
    rad_scene *s = NULL;
    rad_status st = rad_scene_new(ctx, 1, "office", &s);
    if (st) return st;
    static const struct {
        const char *name;
        double rho[3], emit;
    } kinds[SURFACES] = {
        [FLOOR] = {"floor", {0.35, 0.33, 0.30}, 0},   [CEILING] = {"ceiling", {0.80, 0.80, 0.80}, 0},
        [WALLS] = {"walls", {0.65, 0.62, 0.55}, 0},   [DESKS] = {"desks", {0.55, 0.40, 0.25}, 0},
        [CHAIRS] = {"chairs", {0.10, 0.12, 0.30}, 0}, [HOUSINGS] = {"lamp-housings", {0.6, 0.6, 0.6}, 0},
        [LAMPS] = {"lamps", {0.8, 0.8, 0.8}, 40},
    };
    uint32_t surf[SURFACES];
    for (int i = 0; i < SURFACES && !st; ++i) {
        rad_material m = {0};
        m.name = (char *)kinds[i].name;
        for (int c = 0; c < 3; ++c) {
            m.reflectance[c] = kinds[i].rho[c];
            m.emission[c] = kinds[i].emit;
        }
        uint32_t material;
        st = rad_scene_add_material(s, &m, &material);
        if (!st) st = rad_scene_add_surface(s, kinds[i].name, material, &surf[i]);
    }
    for (int i = 0; i < nx && !st; ++i)
        for (int k = 0; k < nz && !st; ++k) st = cell(s, surf, i, k);
    /* Partition walls on room boundaries (the middle cell edge of each room side is a door),
     * then the outer walls facing in. */
    for (int i = ROOM; i < nx && !st; i += ROOM)
        for (int k = 0; k < nz && !st; ++k)
            if (k % ROOM != ROOM / 2) st = wall(s, surf[WALLS], i * CELL, k * CELL, i * CELL, (k + 1) * CELL);
    for (int k = ROOM; k < nz && !st; k += ROOM)
        for (int i = 0; i < nx && !st; ++i)
            if (i % ROOM != ROOM / 2) st = wall(s, surf[WALLS], i * CELL, k * CELL, (i + 1) * CELL, k * CELL);
    double X = nx * CELL, Z = nz * CELL;
    if (!st) st = quad(s, surf[WALLS], v3(0, 0, 0), v3(X, 0, 0), v3(X, HEIGHT, 0), v3(0, HEIGHT, 0));
    if (!st) st = quad(s, surf[WALLS], v3(0, 0, Z), v3(0, HEIGHT, Z), v3(X, HEIGHT, Z), v3(X, 0, Z));
    if (!st) st = quad(s, surf[WALLS], v3(0, 0, 0), v3(0, HEIGHT, 0), v3(0, HEIGHT, Z), v3(0, 0, Z));
    if (!st) st = quad(s, surf[WALLS], v3(X, 0, 0), v3(X, 0, Z), v3(X, HEIGHT, Z), v3(X, HEIGHT, 0));
    if (st) {
        rad_scene_destroy(s);
        return st;
    }
    s->has_camera = 1;
    s->camera = (rad_camera){v3(0.4, 1.6, 0.4), v3(fmin(X, 12), 1.0, fmin(Z, 12)), v3(0, 1, 0), 70};
    *out = s;
    return RAD_OK;
}
