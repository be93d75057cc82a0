/* cmd_scenes.c - `radiosity scenes`: lists the built-in scenes; with --export, writes a
 * geometric scene (a built-in name or any file the importer reads) as OBJ + MTL; with --info,
 * says what a scene holds (text, or one JSON object with --json). */
#include "cli.h"
#include "json.h"
#include "light_options.h"
#include "output_path.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* --generate KIND TRIANGLES FILE.obj. */
static int cli_scenes_generate(const char *kind, const char **positional, int count, int quiet) {
    if (strcmp(kind, "house") == 0) {
        if (count != 1)
            return cli_error(EXIT_USAGE, "scenes: --generate house needs an output file (usage: "
                             "radiosity scenes --generate house FILE.obj)");
        int status = cli_check_output_path("scenes", positional[0], NULL, 0);
        if (status) return status;
        rad_context *ctx = cli_context(1, 0, 0, quiet);
        rad_scene *scene = NULL;
        rad_status rs = rad_scene_generate_house(ctx, &scene);
        if (!rs) rs = rad_scene_export_obj(ctx, scene, positional[0]);
        int exit_status = rs ? cli_fail(ctx, rs) : 0;
        rad_scene_destroy(scene);
        rad_context_destroy(ctx);
        return exit_status;
    }
    if (strcmp(kind, "office") != 0)
        return cli_error(EXIT_USAGE, "scenes: unknown generator '%s' (office, house)", kind);
    if (count != 2)
        return cli_error(EXIT_USAGE, "scenes: --generate office needs a triangle count and an "
                         "output file (usage: radiosity scenes --generate office TRIANGLES FILE.obj)");
    char *end;
    errno = 0;
    unsigned long long triangles = strtoull(positional[0], &end, 10);
    if (end == positional[0] || *end || errno || positional[0][0] == '-' || triangles < 123 ||
        triangles > 200000000)
        return cli_error(EXIT_USAGE, "scenes: the triangle count must be a whole number from 123 "
                         "to 200000000, not '%s'", positional[0]);
    int status = cli_check_output_path("scenes", positional[1], NULL, 0);
    if (status) return status;
    rad_context *ctx = cli_context(1, 0, 0, quiet);
    rad_scene *scene = NULL;
    rad_status rs = rad_scene_generate_office(ctx, (size_t)triangles, &scene);
    if (!rs) rs = rad_scene_export_obj(ctx, scene, positional[1]);
    int exit_status = rs ? cli_fail(ctx, rs) : 0;
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}

/* ---- --info ------------------------------------------------------------------------------ */

/* The import's warnings and notes, kept for the listing as well as shown on stderr. */
#define KEPT_MESSAGES 256
typedef struct kept_log {
    int quiet, json;
    size_t count;
    char *messages[KEPT_MESSAGES];
    int warning[KEPT_MESSAGES];
} kept_log;

static void keep_message(void *user, rad_log_level level, const char *message) {
    kept_log *log = user;
    if (!log->quiet || level == RAD_LOG_WARNING)
        fprintf(stderr, "radiosity: %s%s\n", level == RAD_LOG_WARNING ? "warning: " : "", message);
    if (log->count < KEPT_MESSAGES && (log->messages[log->count] = strdup(message)))
        log->warning[log->count++] = level == RAD_LOG_WARNING;
}

static void print_vector(const double v[3]) { printf("%g %g %g", v[0], v[1], v[2]); }

/* Candela per W/sr and lux per W/m^2: the luminous efficacy of docs/units.md. */
#define RAD_CANDELA_PER_WATT 179.0

static void json_vector(const char *key, const double v[3], int last) {
    printf("\"%s\": ", key);
    json_rgb(stdout, v);
    if (!last) printf(", ");
}

static void info_text(const char *name, const rad_scene *scene, const kept_log *log) {
    rad_scene_info info;
    rad_scene_get_info(scene, &info);
    printf("scene       %s\n", name);
    if (!info.geometric) {
        printf("kind        patch system (given form factors), %zu patches\n", info.patch_count);
        return;
    }
    printf("bounds      ");
    print_vector(info.bounds_min);
    printf("  to  ");
    print_vector(info.bounds_max);
    printf("\npolygons    %zu (%zu triangles), %zu vertices\n", info.polygon_count,
           info.triangle_count, info.vertex_count);
    printf("surfaces    %zu, %zu emitting\n", info.surface_count, info.emitting_surface_count);
    printf("materials   %zu, %zu textures\n", info.material_count, info.texture_count);
    rad_camera_desc camera;
    rad_scene_get_camera(scene, &camera);
    printf("camera      %s: eye ", info.has_camera         ? "the file's"
                                   : info.camera_automatic ? "none in the file; automatic, inside"
                                                           : "none in the file; framing the scene");
    print_vector(camera.eye);
    printf(", look ");
    print_vector(camera.look);
    printf(", up ");
    print_vector(camera.up);
    printf(", vertical field of view %g degrees\n", camera.fov_degrees);
    printf("lights      ");
    size_t shown = 0;
    for (size_t i = 0; i < info.surface_count; ++i) {
        rad_surface_listing surface;
        rad_material_info material;
        if (rad_scene_get_surface(scene, i, &surface) ||
            rad_scene_get_material(scene, surface.material, &material))
            continue;
        const double *e = material.emission;
        if (e[0] > 0 || e[1] > 0 || e[2] > 0)
            printf("%s'%s' (radiance %g %g %g)", shown++ ? ", " : "", surface.name, e[0], e[1], e[2]);
    }
    size_t light_count = rad_scene_light_count(scene);
    rad_sky_desc sky;
    rad_scene_get_sky(scene, &sky);
    int any = shown || light_count || sky.model != RAD_SKY_NONE;
    printf("%s\n", any ? (shown ? "" : "(no emitting surface)") : "none: nothing emits");
    for (size_t i = 0; i < light_count; ++i) {
        rad_light_info l;
        if (rad_scene_get_light(scene, i, &l)) continue;
        const double *I = l.intensity, cd = RAD_CANDELA_PER_WATT;
        if (l.type == RAD_LIGHT_TYPE_DIRECTIONAL) {
            printf("  directional '%s' travelling ", l.name);
            print_vector(l.direction);
            printf(": irradiance %g %g %g W/m^2 (%g %g %g lux)\n", I[0], I[1], I[2], cd * I[0],
                   cd * I[1], cd * I[2]);
            continue;
        }
        printf("  %s '%s' at ", l.type == RAD_LIGHT_TYPE_SPOT ? "spot" : "point", l.name);
        print_vector(l.position);
        if (l.type == RAD_LIGHT_TYPE_SPOT) {
            printf(", axis ");
            print_vector(l.direction);
            printf(", cone %g to %g degrees", l.inner_degrees, l.outer_degrees);
        }
        printf(": intensity %g %g %g W/sr (%g %g %g cd)", I[0], I[1], I[2], cd * I[0], cd * I[1],
               cd * I[2]);
        if (l.ies) printf(", IES profile %s", l.ies);
        printf("\n");
    }
    if (sky.model != RAD_SKY_NONE)
        printf("  sky %s, radiance %g %g %g W/(m^2 sr)%s, zenith %g %g %g\n",
               sky.model == RAD_SKY_MODEL_CIE_OVERCAST ? "CIE overcast" : "uniform",
               sky.radiance[0], sky.radiance[1], sky.radiance[2],
               sky.model == RAD_SKY_MODEL_CIE_OVERCAST ? " at the zenith" : "", sky.up[0],
               sky.up[1], sky.up[2]);
    printf("\nmaterials\n");
    for (size_t i = 0; i < info.material_count; ++i) {
        rad_material_info m;
        if (rad_scene_get_material(scene, i, &m)) continue;
        printf("  %-24s %-7s reflectance %.3g %.3g %.3g", m.name, m.kind, m.reflectance[0],
               m.reflectance[1], m.reflectance[2]);
        if (m.emission[0] > 0 || m.emission[1] > 0 || m.emission[2] > 0)
            printf("  emission %g %g %g", m.emission[0], m.emission[1], m.emission[2]);
        if (m.texture) printf("  texture %s (%u x %u)", m.texture, m.texture_width, m.texture_height);
        printf("  %zu surfaces\n", m.surface_count);
    }
    printf("\nsurfaces (material, polygons, triangles, area)\n");
    for (size_t i = 0; i < info.surface_count; ++i) {
        rad_surface_listing surface;
        rad_material_info m;
        if (rad_scene_get_surface(scene, i, &surface) ||
            rad_scene_get_material(scene, surface.material, &m))
            continue;
        printf("  %-24s %-20s %8zu %8zu %12g%s\n", surface.name, m.name, surface.polygon_count,
               surface.triangle_count, surface.area, surface.textured ? "  textured" : "");
    }
    size_t warnings = 0;
    for (size_t i = 0; i < log->count; ++i) warnings += (size_t)log->warning[i];
    printf("\nwarnings    %zu (shown above on stderr)\n", warnings);
}

static void info_json(const char *name, const rad_scene *scene, const kept_log *log) {
    rad_scene_info info;
    rad_scene_get_info(scene, &info);
    printf("{\"scene\": ");
    json_string(stdout, name);
    printf(", \"geometric\": %s", info.geometric ? "true" : "false");
    if (!info.geometric) {
        printf(", \"patches\": %zu", info.patch_count);
    } else {
        printf(", \"vertices\": %zu, \"polygons\": %zu, \"triangles\": %zu, \"bounds\": {",
               info.vertex_count, info.polygon_count, info.triangle_count);
        json_vector("min", info.bounds_min, 0);
        json_vector("max", info.bounds_max, 1);
        rad_camera_desc camera;
        rad_scene_get_camera(scene, &camera);
        printf("},\n \"camera\": {\"from_file\": %s, \"automatic\": \"%s\", ",
               info.has_camera ? "true" : "false",
               info.has_camera ? "none" : info.camera_automatic ? "inside" : "framing");
        json_vector("eye", camera.eye, 0);
        json_vector("look", camera.look, 0);
        json_vector("up", camera.up, 0);
        printf("\"fov_degrees\": ");
        json_number(stdout, camera.fov_degrees);
        printf("},\n \"materials\": [");
        for (size_t i = 0; i < info.material_count; ++i) {
            rad_material_info m;
            if (rad_scene_get_material(scene, i, &m)) continue;
            printf("%s\n  {\"name\": ", i ? "," : "");
            json_string(stdout, m.name);
            printf(", \"kind\": \"%s\", ", m.kind);
            json_vector("reflectance", m.reflectance, 0);
            json_vector("emission", m.emission, 0);
            printf("\"texture\": ");
            if (m.texture) {
                printf("{\"file\": ");
                json_string(stdout, m.texture);
                printf(", \"width\": %u, \"height\": %u}", m.texture_width, m.texture_height);
            } else {
                printf("null");
            }
            printf(", \"surfaces\": %zu}", m.surface_count);
        }
        printf("],\n \"surfaces\": [");
        size_t lights = 0;
        for (size_t i = 0; i < info.surface_count; ++i) {
            rad_surface_listing s;
            if (rad_scene_get_surface(scene, i, &s)) continue;
            printf("%s\n  {\"name\": ", i ? "," : "");
            json_string(stdout, s.name);
            printf(", \"material\": %zu, \"polygons\": %zu, \"triangles\": %zu, \"area\": ",
                   s.material, s.polygon_count, s.triangle_count);
            json_number(stdout, s.area);
            printf(", \"textured\": %s}", s.textured ? "true" : "false");
        }
        printf("],\n \"lights\": [");
        for (size_t i = 0; i < info.surface_count; ++i) {
            rad_surface_listing s;
            rad_material_info m;
            if (rad_scene_get_surface(scene, i, &s) || rad_scene_get_material(scene, s.material, &m))
                continue;
            if (!(m.emission[0] > 0 || m.emission[1] > 0 || m.emission[2] > 0)) continue;
            printf("%s{\"kind\": \"surface\", \"name\": ", lights++ ? ", " : "");
            json_string(stdout, s.name);
            printf(", ");
            json_vector("radiance", m.emission, 1);
            printf("}");
        }
        for (size_t i = 0; i < rad_scene_light_count(scene); ++i) {
            rad_light_info l;
            if (rad_scene_get_light(scene, i, &l)) continue;
            static const char *const kinds[] = {"point", "spot", "directional"};
            double photometric[3];
            for (int c = 0; c < 3; ++c) photometric[c] = RAD_CANDELA_PER_WATT * l.intensity[c];
            printf("%s\n  {\"kind\": \"%s\", \"name\": ", lights++ ? "," : "",
                   kinds[l.type <= RAD_LIGHT_TYPE_DIRECTIONAL ? l.type : 0]);
            json_string(stdout, l.name);
            printf(", ");
            if (l.type == RAD_LIGHT_TYPE_DIRECTIONAL) {
                json_vector("direction", l.direction, 0);
                json_vector("irradiance_w_m2", l.intensity, 0);
                json_vector("illuminance_lux", photometric, 1);
                printf("}");
                continue;
            }
            json_vector("position", l.position, 0);
            json_vector("direction", l.direction, 0);
            json_vector("intensity_w_sr", l.intensity, 0);
            json_vector("intensity_cd", photometric, 0);
            if (l.type == RAD_LIGHT_TYPE_SPOT) {
                printf("\"inner_degrees\": ");
                json_number(stdout, l.inner_degrees);
                printf(", \"outer_degrees\": ");
                json_number(stdout, l.outer_degrees);
                printf(", ");
            }
            printf("\"ies\": ");
            if (l.ies) json_string(stdout, l.ies);
            else printf("null");
            printf("}");
        }
        rad_sky_desc sky;
        rad_scene_get_sky(scene, &sky);
        if (sky.model != RAD_SKY_NONE) {
            printf("%s\n  {\"kind\": \"sky\", \"model\": \"%s\", ", lights++ ? "," : "",
                   sky.model == RAD_SKY_MODEL_CIE_OVERCAST ? "cie-overcast" : "uniform");
            json_vector("radiance", sky.radiance, 0);
            json_vector("zenith", sky.up, 1);
            printf("}");
        }
        printf("]");
    }
    printf(",\n \"warnings\": [");
    size_t shown = 0;
    for (size_t i = 0; i < log->count; ++i) {
        if (!log->warning[i]) continue;
        if (shown++) printf(", ");
        json_string(stdout, log->messages[i]);
    }
    printf("],\n \"notes\": [");
    shown = 0;
    for (size_t i = 0; i < log->count; ++i) {
        if (log->warning[i]) continue;
        if (shown++) printf(", ");
        json_string(stdout, log->messages[i]);
    }
    printf("]}\n");
}

static int cli_scenes_info(const char *name, int json, int quiet, double max_memory) {
    kept_log log = {quiet || json, json, 0, {0}, {0}};
    rad_context_options options = {0};
    options.log = keep_message;
    options.log_user = &log;
    options.max_memory = max_memory > 0 ? (uint64_t)(max_memory * 1048576.0) : 0;
    rad_context *ctx = NULL;
    if (rad_context_create(&options, &ctx)) return cli_error(1, "cannot create a context");
    rad_scene *scene = NULL;
    rad_status rs = cli_load_scene(ctx, name, &scene);
    int exit_status = 0;
    if (rs) exit_status = cli_fail(ctx, rs);
    else if (json) info_json(name, scene, &log);
    else info_text(name, scene, &log);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    for (size_t i = 0; i < log.count; ++i) free(log.messages[i]);
    return exit_status;
}

int cmd_scenes(int argc, char **argv) {
    static const char synopsis[] = "[--export SCENE FILE.obj | --generate office TRIANGLES "
                                   "FILE.obj | --generate house FILE.obj | --info SCENE [--json]]   "
                                   "(without options: list the built-in scenes)";
    const char *export_scene = NULL, *generate = NULL, *info = NULL;
    int quiet = 0, json = 0;
    cli_light_args lights = {0}; /* --info: the scene as solve and render would take it */
    double max_memory = 0;
    const cli_option options[] = {
        {"--export", CLI_STRING, &export_scene,
         "SCENE FILE.obj  write a geometric scene (built-in or file) as OBJ, with FILE.mtl"},
        {"--generate", CLI_STRING, &generate,
         "office TRIANGLES FILE.obj  write a generated lit open-plan office of about that many "
         "triangles; house FILE.obj: a closed two-room house on a slab (leak test)"},
        {"--quiet", CLI_FLAG, &quiet, "no notes on stderr"},
        {"--info", CLI_STRING, &info,
         "SCENE  what the scene holds: surfaces, materials and textures, lights, camera, bounds, "
         "polygon and triangle counts, warnings"},
        {"--json", CLI_FLAG, &json, "with --info: one JSON object on stdout"},
        CLI_LIGHT_OPTIONS(&lights),
        CLI_TWO_SIDED_OPTION(&lights),
        {"--max-memory", CLI_MEMORY, &max_memory, "MIB  memory budget, in MiB or as 512M, 2G (2048)"},
        {0},
    };
    const char *positional[2];
    int count;
    int status = cli_parse("scenes", synopsis, options, argc, argv, positional, 2, &count);
    if (status) return status < 0 ? 0 : status;
    if (generate) return cli_scenes_generate(generate, positional, count, quiet);
    if (info) {
        if (count)
            return cli_error(EXIT_USAGE, "scenes: unexpected argument '%s' (usage: radiosity "
                             "scenes --info SCENE [--json])", positional[0]);
        if ((status = cli_lights_check("scenes", &lights))) return status;
        return cli_scenes_info(info, json, quiet, max_memory);
    }
    if (json)
        return cli_error(EXIT_USAGE, "scenes: --json goes with --info (usage: radiosity scenes "
                         "--info SCENE --json)");
    if (!export_scene) {
        if (count)
            return cli_error(EXIT_USAGE, "scenes: unexpected argument '%s' (usage: radiosity "
                             "scenes %s)", positional[0], synopsis);
        for (size_t i = 0; i < rad_builtin_scene_count(); ++i)
            printf("%-16s %s\n", rad_builtin_scene_name(i), rad_builtin_scene_description(i));
        return 0;
    }
    if (count > 1)
        return cli_error(EXIT_USAGE, "scenes: unexpected argument '%s' (usage: radiosity scenes "
                         "%s)", positional[1], synopsis);
    if (count != 1)
        return cli_error(EXIT_USAGE, "scenes: --export needs a scene and an output file "
                         "(usage: radiosity scenes --export SCENE FILE.obj)");
    if ((status = cli_check_output_path("scenes", positional[0], &export_scene, 1))) return status;

    rad_context *ctx = cli_context(1, 0, 0, quiet);
    rad_scene *scene = NULL;
    rad_status rs = cli_load_scene(ctx, export_scene, &scene);
    const char *output = positional[0];
    int exit_status = rs ? 0 : cli_check_outputs_against_scene("scenes", scene, &output, 1);
    if (!rs && !exit_status) rs = rad_scene_export_obj(ctx, scene, positional[0]);
    if (rs) exit_status = cli_fail(ctx, rs);
    rad_scene_destroy(scene);
    rad_context_destroy(ctx);
    return exit_status;
}
