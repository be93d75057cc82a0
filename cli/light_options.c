/* light_options.c - --sky, --sun and --ies (light_options.h). */
#include "light_options.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The flags of this run, copied (their strings point into argv, which lives as long as the
 * process). */
static cli_light_args registered;
static int have_registered;

/* Up to `most` comma-separated finite numbers; their count, or -1 when a word is not one. */
static int parse_numbers(const char *text, double *out, int most) {
    int count = 0;
    const char *p = text;
    for (;;) {
        char *end;
        if (count == most) return -1;
        out[count] = strtod(p, &end);
        if (end == p || !isfinite(out[count])) return -1;
        ++count;
        if (*end == '\0') return count;
        if (*end != ',') return -1;
        p = end + 1;
    }
}

int cli_lights_check(const char *command, cli_light_args *a) {
    if (a->sky) {
        const char *values = a->sky;
        rad_sky_model model = RAD_SKY_MODEL_UNIFORM;
        if (strncmp(values, "uniform:", 8) == 0) {
            values += 8;
        } else if (strncmp(values, "cie-overcast:", 13) == 0) {
            values += 13;
            model = RAD_SKY_MODEL_CIE_OVERCAST;
        }
        double v[3];
        int n = parse_numbers(values, v, 3);
        if (!(n == 1 || n == 3) || v[0] < 0 || v[n - 1] < 0 || (n == 3 && v[1] < 0))
            return cli_error(EXIT_USAGE, "%s: --sky takes [uniform:|cie-overcast:]L or R,G,B, "
                             "finite radiances >= 0, not '%s'", command, a->sky);
        memset(&a->sky_desc, 0, sizeof a->sky_desc);
        a->sky_desc.model = model;
        for (int c = 0; c < 3; ++c) a->sky_desc.radiance[c] = v[n == 3 ? c : 0];
    }
    if (a->sun) {
        double v[4];
        int n = parse_numbers(a->sun, v, 4);
        if (n != 4 || !(v[3] >= 0) || !(fabs(v[0]) + fabs(v[1]) + fabs(v[2]) > 0))
            return cli_error(EXIT_USAGE, "%s: --sun takes X,Y,Z,E: a direction towards the sun "
                             "(not zero) and an irradiance E >= 0 in W/m^2, not '%s'", command,
                             a->sun);
        memset(&a->sun_desc, 0, sizeof a->sun_desc);
        a->sun_desc.name = "sun";
        a->sun_desc.type = RAD_LIGHT_TYPE_DIRECTIONAL;
        for (int c = 0; c < 3; ++c) a->sun_desc.direction[c] = -v[c];
        a->sun_desc.strength = v[3];
        a->sun_desc.units = RAD_LIGHT_WATTS;
    }
    if (a->ies) {
        const char *equals = strchr(a->ies, '=');
        a->ies_name[0] = '\0';
        a->ies_path = a->ies;
        if (equals) {
            size_t length = (size_t)(equals - a->ies);
            if (length == 0 || length >= sizeof a->ies_name || !equals[1])
                return cli_error(EXIT_USAGE, "%s: --ies takes [NAME=]FILE, not '%s'", command,
                                 a->ies);
            memcpy(a->ies_name, a->ies, length);
            a->ies_name[length] = '\0';
            a->ies_path = equals + 1;
        }
        if (!*a->ies_path) return cli_error(EXIT_USAGE, "%s: --ies needs a file", command);
    }
    a->specular_on = -1;
    a->specular_photon_count = 0;
    if (a->specular_first) {
        if (strcmp(a->specular_first, "1") == 0) a->specular_on = 1;
        else if (strcmp(a->specular_first, "0") == 0) a->specular_on = 0;
        else
            return cli_error(EXIT_USAGE, "%s: --specular-first takes 1 or 0, not '%s'", command,
                             a->specular_first);
    }
    if (a->specular_photons) {
        char *end;
        const char *text = a->specular_photons;
        unsigned long long n = strtoull(text, &end, 10);
        if (end == text || *end || text[0] == '-' || text[0] == '+' || n < 1 || n > 1000000000ull)
            return cli_error(EXIT_USAGE, "%s: --specular-photons takes a whole number from 1 to "
                             "10^9, not '%s'", command, text);
        a->specular_photon_count = n;
    }
    registered = *a;
    have_registered = 1;
    return 0;
}

rad_status cli_lights_apply(rad_scene *scene) {
    if (!have_registered) return RAD_OK;
    const cli_light_args *a = &registered;
    rad_status status = a->two_sided ? rad_scene_set_two_sided(scene) : RAD_OK;
    if (!status && a->sky) status = rad_scene_set_sky(scene, &a->sky_desc);
    if (!status && a->sun) status = rad_scene_add_light(scene, &a->sun_desc);
    if (!status && a->ies)
        status = rad_scene_set_light_ies(scene, a->ies_name[0] ? a->ies_name : NULL, a->ies_path);
    if (!status && (a->specular_first || a->specular_photons))
        status = rad_scene_set_specular_first(scene, a->specular_on, a->specular_photon_count);
    return status;
}
