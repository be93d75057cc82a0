/* generate_house.c - a small closed house for finding light that leaves the room (issue 16):
 * two rooms side by side (4.1 m and 4.1 m by 6.4 m, 2.6 m high) with a doorway between them and
 * one ceiling lamp in the west room. It is built the way building models are (IFC exports):
 *   - a floor slab 0.3 m thick that runs under the walls and 1 m out of the building;
 *   - exterior walls 0.2 m thick that pass through the floor slab and through the roof slab
 *     (from 0.2 m below the floor to 0.1 m above the roof), solids whose faces cross the slabs';
 *   - a partition wall standing on the floor slab and reaching the ceiling, with a doorway;
 *   - a roof slab whose underside is the ceiling, wider than the building.
 * Every solid is closed where it shows; faces that lie inside another solid (a wall's bottom in
 * the slab) are left out. Nothing leaves the house, so at convergence all emitted power is
 * absorbed inside: a radiosity solution that reports power escaping (`solve --json`,
 * "energy") leaks, through elements that straddle a wall (lit inside, dark outside).
 * Units are metres; deterministic. */
#include "scene/scene.h"

#include <math.h>

enum { SLAB, ROOF, WALLS, PARTITION, LINTEL, LAMP, HOUSE_SURFACES };

/* Box faces by their outward axis: +x, -x, +y, -y, +z, -z. */
enum { F_PX = 1, F_NX = 2, F_PY = 4, F_NY = 8, F_PZ = 16, F_NZ = 32, F_ALL = 63 };

/* Each face's corners as (x, y, z) choices of lo (0) or hi (1), counter-clockwise from outside. */
static const unsigned char face_corners[6][4][3] = {
    {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, /* +x */
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, /* -x */
    {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, /* +y */
    {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, /* -y */
    {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, /* +z */
    {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, /* -z */
};

/* The faces of the solid box lo..hi chosen by `faces`, facing out. */
static rad_status solid(rad_scene *s, uint32_t surface, rad_vec3 lo, rad_vec3 hi, int faces) {
    for (int f = 0; f < 6; ++f) {
        if (!(faces & (1 << f))) continue;
        rad_vec3 p[4];
        for (int k = 0; k < 4; ++k) {
            const unsigned char *c = face_corners[f][k];
            p[k] = v3(c[0] ? hi.x : lo.x, c[1] ? hi.y : lo.y, c[2] ? hi.z : lo.z);
        }
        rad_status st = rad_scene_add_polygon_points(s, surface, p, 4);
        if (st) return st;
    }
    return RAD_OK;
}

/* A diffuse surface of its own material: reflectance (r, g, b), emission E in every channel. */
static rad_status plain_surface(rad_scene *s, const char *name, double r, double g, double b,
                                double emission, uint32_t *surface) {
    rad_material m = {0};
    m.name = (char *)name;
    m.reflectance[0] = r, m.reflectance[1] = g, m.reflectance[2] = b;
    m.emission[0] = m.emission[1] = m.emission[2] = emission;
    uint32_t material;
    rad_status st = rad_scene_add_material(s, &m, &material);
    return st ? st : rad_scene_add_surface(s, name, material, surface);
}

rad_status rad_scene_generate_house(rad_context *ctx, rad_scene **out) {
    *out = NULL;
    rad_scene *s = NULL;
    rad_status st = rad_scene_new(ctx, 1, "house", &s);
    if (st) return st;
    uint32_t surf[HOUSE_SURFACES];
    if (!st) st = plain_surface(s, "floor-slab", 0.45, 0.40, 0.35, 0, &surf[SLAB]);
    if (!st) st = plain_surface(s, "roof-slab", 0.75, 0.75, 0.72, 0, &surf[ROOF]);
    if (!st) st = plain_surface(s, "exterior-walls", 0.70, 0.66, 0.60, 0, &surf[WALLS]);
    if (!st) st = plain_surface(s, "partition", 0.60, 0.65, 0.70, 0, &surf[PARTITION]);
    if (!st) st = plain_surface(s, "door-lintel", 0.60, 0.65, 0.70, 0, &surf[LINTEL]);
    if (!st) st = plain_surface(s, "lamp", 0.80, 0.80, 0.80, 60, &surf[LAMP]);
    /* Inside: x 0..8.4 (the partition at 4.1..4.3), y 0..2.6, z 0..6.4. */
    const double X = 8.4, H = 2.6, Z = 6.4, T = 0.2;
    /* Floor slab, out of the building by 1 m; roof slab by 0.5 m. */
    if (!st) st = solid(s, surf[SLAB], v3(-1, -0.3, -1), v3(X + 1, 0, Z + 1), F_ALL);
    if (!st) st = solid(s, surf[ROOF], v3(-0.5, H, -0.5), v3(X + 0.5, H + 0.3, Z + 0.5), F_ALL);
    /* Exterior walls through both slabs, from inside the floor slab (their bottoms, in it, are
     * left out) to 0.1 m above the roof; the west and east walls end against the south and
     * north walls (their ends, inside those, are left out too). */
    double y0 = -0.2, y1 = H + 0.4;
    const int sides = F_ALL & ~F_NY;
    if (!st) st = solid(s, surf[WALLS], v3(-T, y0, -T), v3(X + T, y1, 0), sides);
    if (!st) st = solid(s, surf[WALLS], v3(-T, y0, Z), v3(X + T, y1, Z + T), sides);
    if (!st) st = solid(s, surf[WALLS], v3(-T, y0, 0), v3(0, y1, Z), sides & ~(F_PZ | F_NZ));
    if (!st) st = solid(s, surf[WALLS], v3(X, y0, 0), v3(X + T, y1, Z), sides & ~(F_PZ | F_NZ));
    /* The partition on the floor slab, up to the ceiling, with a doorway 1 m wide, 2.1 m high
     * (its ends, bottom and top touch the walls and slabs and are left out). The lintel over
     * the doorway is a surface of its own: contact cuts are made between surfaces only
     * (mesh/contact.c), and the jambs' upper parts lie against its ends. */
    const double px0 = 4.1, px1 = 4.3, d0 = 2.7, d1 = 3.7, door = 2.1;
    if (!st) st = solid(s, surf[PARTITION], v3(px0, 0, 0), v3(px1, H, d0), F_PX | F_NX | F_PZ);
    if (!st) st = solid(s, surf[PARTITION], v3(px0, 0, d1), v3(px1, H, Z), F_PX | F_NX | F_NZ);
    if (!st) st = solid(s, surf[LINTEL], v3(px0, door, d0), v3(px1, H, d1), F_PX | F_NX | F_NY);
    /* The lamp: a 0.6 m square panel 1 cm under the ceiling of the west room, facing down. */
    if (!st) st = solid(s, surf[LAMP], v3(1.75, H - 0.01, 2.9), v3(2.35, H - 0.01, 3.5), F_NY);
    if (st) {
        rad_scene_destroy(s);
        return st;
    }
    /* From the west room's south-west corner towards the doorway and the east room. */
    s->has_camera = 1;
    s->camera = (rad_camera){v3(0.3, 1.7, 0.3), v3(4.2, 1.0, 3.4), v3(0, 1, 0), 75};
    *out = s;
    return RAD_OK;
}
