/* export_obj.c - a geometric scene as Wavefront OBJ + MTL (rad_scene_export_obj).
 *
 * Written here rather than with assimp's exporter (aiExportScene): an aiScene cannot be built
 * through assimp's C API (materials are property tables that only the C++ side can fill), and
 * writing the text ourselves keeps every surface name, the number format (the shortest decimal
 * that reads back to the same double) and the write-then-rename discipline in our hands.
 *
 * Layout: a header comment (source, camera), `mtllib`, then per surface `o NAME`, `usemtl`,
 * the surface's vertices and its faces (1-based, counter-clockwise as in the scene). The MTL
 * file has Kd (reflectance), Ke (emitted radiance L, docs/units.md) and, for mirrors and glass,
 * illum/Ks/Ns or illum/Ni/Tf, the inverse of what the importer reads. */
#include "core/atomic_file.h"
#include "scene/scene.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The shortest of %.15g, %.16g, %.17g that reads back as the same double. */
static void format_number(char *text, size_t size, double value) {
    for (int digits = 15; digits <= 17; ++digits) {
        snprintf(text, size, "%.*g", digits, value);
        if (strtod(text, NULL) == value) return;
    }
}

static int write_triple(FILE *file, const char *key, const double v[3]) {
    char a[32], b[32], c[32];
    format_number(a, sizeof a, v[0]);
    format_number(b, sizeof b, v[1]);
    format_number(c, sizeof c, v[2]);
    return fprintf(file, "%s %s %s %s\n", key, a, b, c) < 0;
}

/* OBJ names end at white space and '#' starts a comment: both become '_'. */
static void clean_name(char *name) {
    for (; *name; ++name)
        if (*name == ' ' || *name == '\t' || *name == '\n' || *name == '\r' || *name == '#')
            *name = '_';
}

/* Material names for `usemtl`: cleaned, empty ones named by index, repeated ones suffixed. */
static char **material_names(rad_context *ctx, const rad_scene *scene) {
    char **names = rad_alloc_zero(ctx, scene->material_count + 1, sizeof *names);
    if (!names) return NULL;
    for (size_t i = 0; i < scene->material_count; ++i) {
        const char *given = scene->materials[i].name;
        size_t length = (given ? strlen(given) : 0) + 32;
        names[i] = rad_alloc(ctx, length, 1);
        if (!names[i]) break;
        if (given && *given) snprintf(names[i], length, "%s", given);
        else snprintf(names[i], length, "material-%zu", i);
        clean_name(names[i]);
        for (size_t j = 0; j < i; ++j)
            if (strcmp(names[i], names[j]) == 0) {
                size_t end = strlen(names[i]);
                snprintf(names[i] + end, length - end, ".%zu", i + 1);
                break;
            }
    }
    return names;
}

static void free_names(rad_context *ctx, char **names, size_t count) {
    if (!names) return;
    for (size_t i = 0; i < count; ++i) rad_free(ctx, names[i]);
    rad_free(ctx, names);
}

static int write_mtl(FILE *file, const rad_scene *scene, char **names) {
    int failed = fprintf(file, "# Materials of %s: Kd = diffuse reflectance, Ke = emitted "
                               "radiance (docs/units.md)\n", scene->source) < 0;
    for (size_t i = 0; i < scene->material_count && !failed; ++i) {
        const rad_material *m = &scene->materials[i];
        failed |= fprintf(file, "\nnewmtl %s\n", names[i]) < 0;
        failed |= write_triple(file, "Kd", m->reflectance);
        if (m->emission[0] != 0 || m->emission[1] != 0 || m->emission[2] != 0)
            failed |= write_triple(file, "Ke", m->emission);
        char number[32];
        switch (m->kind) {
        case RAD_MATERIAL_DIFFUSE: failed |= fprintf(file, "illum 1\n") < 0; break;
        case RAD_MATERIAL_MIRROR: {
            /* Ns = 1000 (1 - roughness)^2, never 0 (which reads back as a perfect mirror). */
            double rough = fmin(1.0, fmax(0.0, m->roughness));
            format_number(number, sizeof number, fmax(1e-6, 1000 * (1 - rough) * (1 - rough)));
            failed |= fprintf(file, "illum 3\n") < 0;
            failed |= write_triple(file, "Ks", m->specular);
            failed |= fprintf(file, "Ns %s\n", number) < 0;
            break;
        }
        case RAD_MATERIAL_GLASS:
            format_number(number, sizeof number, m->ior);
            failed |= fprintf(file, "illum 7\nNi %s\n", number) < 0;
            failed |= write_triple(file, "Tf", m->specular);
            break;
        }
    }
    return failed;
}

static int write_obj(rad_context *ctx, FILE *file, const rad_scene *scene, char **material_name,
                     const char *mtl_name, const size_t *order, const size_t *first,
                     uint32_t *obj_index) {
    int failed = fprintf(file, "# %s, written by radiosity. Lengths in scene units; faces are "
                               "counter-clockwise seen from the front.\n", scene->source) < 0;
    if (scene->has_camera) {
        /* For people: OBJ has no cameras, and the importer does not read this line. */
        const rad_camera *c = &scene->camera;
        const double values[10] = {c->eye.x, c->eye.y, c->eye.z, c->look.x, c->look.y,
                                   c->look.z, c->up.x, c->up.y, c->up.z, c->fov_degrees};
        char text[10][32];
        for (int i = 0; i < 10; ++i) format_number(text[i], sizeof text[i], values[i]);
        failed |= fprintf(file, "# camera: eye %s %s %s  look %s %s %s  up %s %s %s  vertical "
                                "field of view %s degrees\n", text[0], text[1], text[2], text[3],
                          text[4], text[5], text[6], text[7], text[8], text[9]) < 0;
    }
    failed |= fprintf(file, "mtllib %s\n", mtl_name) < 0;
    for (size_t i = 0; i < scene->vertex_count; ++i) obj_index[i] = 0;
    uint32_t written = 0;
    for (size_t s = 0; s < scene->surface_count && !failed; ++s) {
        if (first[s] == first[s + 1]) continue;
        const rad_surface_def *surface = &scene->surfaces[s];
        size_t length = strlen(surface->name) + 32;
        char *name = rad_alloc(ctx, length, 1);
        if (!name) return -1; /* out of memory: the message is on the context */
        if (surface->name[0]) snprintf(name, length, "%s", surface->name);
        else snprintf(name, length, "surface-%zu", s);
        clean_name(name);
        failed |= fprintf(file, "\no %s\nusemtl %s\n", name, material_name[surface->material]) < 0;
        rad_free(ctx, name);
        /* The surface's vertices, each once, then its faces. Vertices shared with an earlier
         * surface are written again, so every object stands alone. */
        uint32_t surface_start = written;
        for (size_t k = first[s]; k < first[s + 1] && !failed; ++k) {
            const rad_polygon *p = &scene->polygons[order[k]];
            for (uint32_t c = 0; c < p->count; ++c) {
                uint32_t v = scene->polygon_vertices[p->first + c];
                if (obj_index[v] > surface_start) continue;
                obj_index[v] = ++written;
                double xyz[3] = {scene->vertices[v].x, scene->vertices[v].y, scene->vertices[v].z};
                failed |= write_triple(file, "v", xyz);
            }
        }
        for (size_t k = first[s]; k < first[s + 1] && !failed; ++k) {
            const rad_polygon *p = &scene->polygons[order[k]];
            failed |= fputc('f', file) == EOF;
            for (uint32_t c = 0; c < p->count; ++c)
                failed |= fprintf(file, " %u", obj_index[scene->polygon_vertices[p->first + c]]) < 0;
            failed |= fputc('\n', file) == EOF;
        }
    }
    return failed;
}

rad_status rad_scene_export_obj(rad_context *ctx, const rad_scene *scene, const char *path) {
    if (!ctx || !scene || !path) return RAD_ERROR_INVALID_ARGUMENT;
    if (!scene->geometric)
        return rad_fail(ctx, RAD_ERROR_INVALID_ARGUMENT, "%s is a patch system with given form "
                        "factors: it has no geometry to write as OBJ", scene->source);
    /* FILE.obj -> FILE.mtl (or FILE + ".mtl" when there is no extension). */
    size_t length = strlen(path);
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - path) : length;
    char *mtl_path = rad_alloc(ctx, stem + 5, 1);
    size_t *order = rad_alloc(ctx, scene->polygon_count + 1, sizeof *order);
    size_t *first = rad_alloc_zero(ctx, scene->surface_count + 2, sizeof *first);
    uint32_t *obj_index = rad_alloc(ctx, scene->vertex_count + 1, sizeof *obj_index);
    char **names = material_names(ctx, scene);
    rad_status status = RAD_OK;
    rad_atomic_file obj = {0}, mtl = {0};
    if (!mtl_path || !order || !first || !obj_index || !names) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    memcpy(mtl_path, path, stem);
    memcpy(mtl_path + stem, ".mtl", 5);

    /* Polygons grouped by surface (a counting sort keeps their order within a surface). */
    for (size_t i = 0; i < scene->polygon_count; ++i) first[scene->polygons[i].surface + 1]++;
    for (size_t s = 0; s < scene->surface_count; ++s) first[s + 1] += first[s];
    for (size_t i = 0; i < scene->polygon_count; ++i) {
        size_t *slot = &first[scene->polygons[i].surface];
        order[(*slot)++] = i;
    }
    for (size_t s = scene->surface_count; s > 0; --s) first[s] = first[s - 1];
    first[0] = 0;

    const char *mtl_base = strrchr(mtl_path, '/') ? strrchr(mtl_path, '/') + 1 : mtl_path;
    /* Both written before either is renamed into place; the .mtl first, so that an .obj never
     * names a missing library. */
    if ((status = rad_atomic_open(ctx, path, &obj))) goto done;
    if ((status = rad_atomic_open(ctx, mtl_path, &mtl))) goto done;
    int failed = write_obj(ctx, obj.file, scene, names, mtl_base, order, first, obj_index);
    failed |= write_mtl(mtl.file, scene, names);
    if (failed < 0) {
        status = RAD_ERROR_NO_MEMORY;
        goto done;
    }
    if ((status = rad_atomic_commit(&mtl))) goto done;
    /* A .mtl written through to a device cannot be taken back; a renamed one is removed. */
    if ((status = rad_atomic_commit(&obj)) && !mtl.direct) remove(mtl_path);
done:
    rad_atomic_abandon(&obj);
    rad_atomic_abandon(&mtl);
    free_names(ctx, names, scene->material_count);
    rad_free(ctx, mtl_path);
    rad_free(ctx, order);
    rad_free(ctx, first);
    rad_free(ctx, obj_index);
    return status;
}
