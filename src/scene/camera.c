/* camera.c - pinhole cameras (see camera.h). */
#include "scene/camera.h"

#include "core/team.h"
#include "scene/rays.h"

#include <string.h>

rad_camera rad_camera_framing(const rad_scene *scene) {
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    if (!scene->vertex_count) lo = hi = v3(0, 0, 0);
    rad_vec3 center = v3_scale(v3_add(lo, hi), 0.5);
    double radius = 0.5 * v3_length(v3_sub(hi, lo));
    if (!(radius > 0)) radius = 1;
    double fov = 40;
    double distance = radius / sin(0.5 * fov * RAD_PI / 180) * 1.05;
    rad_camera camera = {v3_sub(center, v3(0, 0, distance)), center, v3(0, 1, 0), fov};
    return camera;
}

rad_camera rad_scene_camera(const rad_scene *scene) {
    return scene->has_camera || scene->camera_automatic ? scene->camera : rad_camera_framing(scene);
}

/* ---- the automatic camera ---------------------------------------------------------------- */

/* Candidate eye points per side of the bounding box, directions cast from each. */
#define AUTO_GRID 10
#define AUTO_DIRECTIONS 64
/* Level view directions tried from the chosen eye, and how far they look down (radians). */
#define AUTO_HEADINGS 32
#define AUTO_PITCH 0.2

/* Front and back hits of a 24 x 24 grid of rays through the camera's image (square). */
static void probe(const rad_rays *rays, const rad_camera *camera, int *fronts, int *hits) {
    rad_view view;
    *fronts = *hits = 0;
    if (rad_view_make(NULL, camera, 24, 24, &view)) return;
    for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 24; ++i) {
            rad_hit hit;
            if (!rad_rays_intersect(rays, view.eye, rad_view_direction(&view, i + 0.5, j + 0.5), 0,
                                    INFINITY, &hit))
                continue;
            ++*hits;
            *fronts += hit.front != 0;
        }
}

/* Direction k of n spread evenly over the sphere (Fibonacci lattice). */
static rad_vec3 sphere_direction(int k, int n) {
    double z = 1 - (2 * k + 1.0) / n, r = sqrt(fmax(0.0, 1 - z * z));
    double phi = k * RAD_PI * (3 - sqrt(5.0));
    return v3(r * cos(phi), z, r * sin(phi));
}

/* Whether the emitting surfaces' light stays inside the scene: of ENCLOSED_RAYS rays from the
 * emitting polygons' centres (every step-th one, in order, when there are more than that) over
 * their front hemispheres, fewer than one in 32 leave it. Such light cannot reach what a camera
 * outside sees (a lamp in a closed house). No emitting surface: 0. */
#define ENCLOSED_RAYS 256
static int light_enclosed(const rad_scene *scene, const rad_rays *rays) {
    size_t lit = 0;
    for (size_t i = 0; i < scene->polygon_count; ++i)
        lit += (size_t)rad_polygon_emits(scene, &scene->polygons[i]);
    if (!lit) return 0;
    rad_vec3 lo, hi;
    rad_scene_bounds(scene, &lo, &hi);
    const double near = 1e-6 * v3_length(v3_sub(hi, lo));
    const size_t step = lit > ENCLOSED_RAYS ? lit / ENCLOSED_RAYS : 1;
    const int per = lit < ENCLOSED_RAYS ? (int)(ENCLOSED_RAYS / lit) : 1; /* rays per polygon */
    int cast = 0, escaped = 0;
    for (size_t i = 0, seen = 0; i < scene->polygon_count && cast < ENCLOSED_RAYS; ++i) {
        const rad_polygon *p = &scene->polygons[i];
        if (!rad_polygon_emits(scene, p) || seen++ % step) continue;
        rad_vec3 centre = v3(0, 0, 0), n = rad_polygon_normal(scene, p);
        for (uint32_t k = 0; k < p->count; ++k)
            centre = v3_add(centre, rad_polygon_vertex(scene, p, k));
        centre = v3_scale(centre, 1.0 / p->count);
        /* A Fibonacci sphere's directions, those behind the polygon mirrored to its front. */
        for (int k = 0; k < per && cast < ENCLOSED_RAYS; ++k, ++cast) {
            rad_vec3 d = sphere_direction(k, per);
            if (v3_dot(d, n) < 0) d = v3_sub(d, v3_scale(n, 2 * v3_dot(d, n)));
            rad_hit hit;
            escaped += !rad_rays_intersect(rays, centre, d, near, INFINITY, &hit);
        }
    }
    return cast > 0 && escaped * 32 < cast;
}

/* The candidate eyes of the automatic camera and their scores. */
typedef struct eye_grid {
    const rad_rays *rays;
    rad_vec3 lo, size;                                /* the scene's bounding box */
    double score[AUTO_GRID * AUTO_GRID * AUTO_GRID]; /* 0: not inside the open space */
} eye_grid;

/* Point g of the grid (a slowest, c fastest). */
static rad_vec3 grid_point(const eye_grid *grid, int g) {
    int a = g / (AUTO_GRID * AUTO_GRID), b = g / AUTO_GRID % AUTO_GRID, c = g % AUTO_GRID;
    return v3(grid->lo.x + grid->size.x * (a + 0.5) / AUTO_GRID,
              grid->lo.y + grid->size.y * (b + 0.5) / AUTO_GRID,
              grid->lo.z + grid->size.z * (c + 0.5) / AUTO_GRID);
}

/* Point g's mean free path over AUTO_DIRECTIONS rays, or 0 when it is not inside: at most one
 * direction in 32 meets a back (a thin gap, a one-sided panel), at least three in four a
 * front. */
static void eye_score(void *user, long g, int worker) {
    (void)worker;
    eye_grid *grid = user;
    rad_vec3 p = grid_point(grid, (int)g);
    int front = 0, back = 0;
    double free_path = 0;
    for (int k = 0; k < AUTO_DIRECTIONS; ++k) {
        rad_hit hit;
        if (!rad_rays_intersect(grid->rays, p, sphere_direction(k, AUTO_DIRECTIONS), 0, INFINITY, &hit))
            continue;
        if (hit.front) {
            ++front;
            free_path += hit.t;
        } else {
            ++back;
        }
    }
    grid->score[g] = back * 32 > AUTO_DIRECTIONS || front * 4 < 3 * AUTO_DIRECTIONS
                         ? 0
                         : free_path / AUTO_DIRECTIONS;
}

void rad_scene_auto_camera(rad_scene *scene) {
    if (!scene->geometric || scene->has_camera || !scene->polygon_count) return;
    rad_context *ctx = scene->ctx;
    rad_rays *rays = NULL;
    if (rad_rays_create(ctx, scene, &rays)) return;
    rad_camera framing = rad_camera_framing(scene);
    int fronts, hits;
    probe(rays, &framing, &fronts, &hits);
    /* An object, or an open scene, seen from outside: the framing camera, unless the light
     * stays inside and there is an open space there (a closed house on a slab that runs out
     * under its walls shows its fronts from outside, unlit: a black picture). */
    if (hits > 0 && 2 * fronts >= hits && !light_enclosed(scene, rays)) {
        rad_rays_destroy(rays);
        return;
    }
    /* The eye: of a grid of points in the bounding box, one that sees front faces all around
     * (inside the open space, not inside a solid or outside the room), with the longest mean
     * free path: the middle of the largest open volume. The points are scored on the
     * context's threads, then taken in grid order. */
    eye_grid grid;
    memset(&grid, 0, sizeof grid);
    rad_vec3 hi;
    grid.rays = rays;
    rad_scene_bounds(scene, &grid.lo, &hi);
    grid.size = v3_sub(hi, grid.lo);
    rad_team_for(ctx, AUTO_GRID * AUTO_GRID * AUTO_GRID, eye_score, &grid);
    double best = 0;
    rad_vec3 eye = v3(0, 0, 0);
    for (int g = 0; g < AUTO_GRID * AUTO_GRID * AUTO_GRID; ++g)
        if (grid.score[g] > best) {
            best = grid.score[g];
            eye = grid_point(&grid, g);
        }
    if (!(best > 0)) {
        rad_rays_destroy(rays); /* no open space inside: the framing camera stays */
        return;
    }
    /* The view: level (a little down), along the heading with the longest free view, +y up. */
    rad_vec3 view = v3(0, 0, 1);
    double farthest = -1;
    for (int k = 0; k < AUTO_HEADINGS; ++k) {
        double heading = 2 * RAD_PI * k / AUTO_HEADINGS;
        rad_vec3 d = v3(cos(heading) * cos(AUTO_PITCH), -sin(AUTO_PITCH), sin(heading) * cos(AUTO_PITCH));
        rad_hit hit;
        double t = rad_rays_intersect(rays, eye, d, 0, INFINITY, &hit) && hit.front ? hit.t : 0;
        if (t > farthest) {
            farthest = t;
            view = d;
        }
    }
    rad_camera camera = {eye, v3_add(eye, view), v3(0, 1, 0), 60};
    probe(rays, &camera, &fronts, &hits);
    rad_rays_destroy(rays);
    if (!fronts) return;
    scene->camera = camera;
    scene->camera_automatic = 1;
    rad_info(ctx, "%s: no camera in the file; the automatic camera stands inside the largest "
             "open space, at %g %g %g, looking towards %g %g %g (set another with --eye and "
             "--look)", scene->source, eye.x, eye.y, eye.z, camera.look.x, camera.look.y,
             camera.look.z);
}

static int finite3(rad_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

rad_status rad_view_make(rad_context *ctx, const rad_camera *camera, int width, int height,
                         rad_view *out) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "image size %dx%d: each side must be 1 to 16384 pixels", width, height);
    if (!finite3(camera->eye) || !finite3(camera->look) || !finite3(camera->up) ||
        !isfinite(camera->fov_degrees))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "camera: values must be finite");
    if (!(camera->fov_degrees > 0 && camera->fov_degrees < 180))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera: field of view must be between 0 and 180 degrees, not %g",
                        camera->fov_degrees);
    rad_vec3 forward = v3_sub(camera->look, camera->eye);
    if (!(v3_length(forward) > 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "camera: eye and look are the same point");
    forward = v3_normalize(forward);
    rad_vec3 right = v3_cross(forward, camera->up);
    if (!(v3_length(right) > 1e-9 * v3_length(camera->up)) || !(v3_length(camera->up) > 0))
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera: up must not be zero or parallel to the view direction");
    right = v3_normalize(right);
    out->eye = camera->eye;
    out->forward = forward;
    out->right = right;
    out->up = v3_cross(right, forward);
    out->tan_half_fov = tan(0.5 * camera->fov_degrees * RAD_PI / 180);
    out->width = width;
    out->height = height;
    return RAD_OK;
}

/* ---- the one camera rule ------------------------------------------------------------------ */

#define CHECK_GRID 64

rad_status rad_view_check(rad_context *ctx, const rad_view *view, rad_view_see see,
                          const void *user) {
    int hits = 0, fronts = 0;
    const char *back_surface = NULL;
    for (int pass = 0; pass < 2 && fronts == 0; ++pass) {
        int nx = pass == 0 && view->width > CHECK_GRID ? CHECK_GRID : view->width;
        int ny = pass == 0 && view->height > CHECK_GRID ? CHECK_GRID : view->height;
        for (int j = 0; j < ny && fronts == 0; ++j)
            for (int i = 0; i < nx && fronts == 0; ++i) {
                double px = (i + 0.5) * view->width / nx, py = (j + 0.5) * view->height / ny;
                int front = 0;
                const char *surface = NULL;
                if (!see(user, view->eye, rad_view_direction(view, px, py), &front, &surface))
                    continue;
                ++hits;
                if (front) ++fronts;
                else if (!back_surface) back_surface = surface;
            }
        if (nx == view->width && ny == view->height) break;
    }
    if (fronts) return RAD_OK;
    if (!hits)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT,
                        "camera sees nothing: no surface in the view (check --eye, --look, --fov)");
    /* Only backs: the picture is what the camera sees, one-sided surfaces from behind, black
     * (as the path tracer draws them); a warning says why it is dark. */
    rad_warn(ctx,
             "the camera sees only the backs of surfaces (such as '%s'), which are one-sided and "
             "drawn black; it may be inside an object or behind the scene (place it with --eye "
             "and --look, or give the surfaces backs with --two-sided)",
             back_surface ? back_surface : "?");
    return RAD_OK;
}

/* ---- the public camera description ---------------------------------------------------- */

void rad_scene_get_camera(const rad_scene *scene, rad_camera_desc *out) {
    rad_camera camera = rad_scene_camera(scene);
    rad_camera_to_desc(&camera, out);
}

void rad_camera_to_desc(const rad_camera *camera, rad_camera_desc *out) {
    const rad_vec3 v[3] = {camera->eye, camera->look, camera->up};
    double *d[3] = {out->eye, out->look, out->up};
    for (int k = 0; k < 3; ++k) {
        d[k][0] = v[k].x;
        d[k][1] = v[k].y;
        d[k][2] = v[k].z;
    }
    out->fov_degrees = camera->fov_degrees;
}

rad_camera rad_camera_from_desc(const rad_camera_desc *desc) {
    rad_camera camera = {
        v3(desc->eye[0], desc->eye[1], desc->eye[2]),
        v3(desc->look[0], desc->look[1], desc->look[2]),
        v3(desc->up[0], desc->up[1], desc->up[2]),
        desc->fov_degrees,
    };
    return camera;
}
