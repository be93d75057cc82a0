/* lights.h - the sources that are not surfaces (docs/lights.md): point, spot and directional
 * lights (from scene files, or the sun of --sun), IES LM-63 intensity profiles, and the sky
 * (--sky). All are "delta" or environment sources: a point or a direction gives light, no
 * surface the rays could hit does, so they are reached by next-event estimation alone (no
 * multiple-importance weights: no other strategy can find them) and by rays that escape the
 * scene (the sky).
 *
 * Units, radiometric (docs/units.md): a point or spot light has radiant intensity I in W/sr, so
 * the irradiance it gives a surface at distance r with incidence angle theta is
 *     E = I(w) cos(theta) / r^2;
 * a directional light (the sun) has irradiance E_perp in W/m^2 on a plane facing it, so
 *     E = E_perp cos(theta);
 * the sky has radiance L(w) in W/m^2/sr over the upper hemisphere (w . up > 0), black below. */
#ifndef RAD_LIGHT_LIGHTS_H
#define RAD_LIGHT_LIGHTS_H

#include "core/context.h"
#include "core/vec3.h"

#include <stddef.h>

/* Luminous efficacy that turns photometric into radiometric quantities, the one the MGF reader
 * uses (Radiance's WHTEFFICACY): 1 W = 179 lm, so 1 cd = 1/179 W/sr, 1 lx = 1/179 W/m^2. */
#define RAD_LUMINOUS_EFFICACY 179.0

/* An IES LM-63 photometric profile (ies.c): candela on a grid of vertical angles (0 = straight
 * down the light's axis, 180 = straight up) and horizontal angles (around the axis). */
typedef struct rad_ies_profile {
    size_t vertical_count, horizontal_count;
    double *vertical;   /* degrees, ascending */
    double *horizontal; /* degrees, ascending */
    double *candela;    /* horizontal_count rows of vertical_count values, multiplier applied */
    double max_candela;
    char file[256]; /* the file it came from, for listings (rad_scene_get_light) */
} rad_ies_profile;

/* Parses LM-63 text (1986, 1991, 1995, 2002 headers; TILT=NONE or an inline TILT=INCLUDE table,
 * which is skipped). `source` names the file in errors, "file:line: what is wrong". */
rad_status rad_ies_parse(rad_context *ctx, const char *text, size_t length, const char *source,
                         rad_ies_profile **out);
rad_status rad_ies_load(rad_context *ctx, const char *path, rad_ies_profile **out);
void rad_ies_free(rad_context *ctx, rad_ies_profile *profile);
/* Candela at (vertical, horizontal) degrees, bilinear between the grid's angles, with the
 * symmetries LM-63 gives by the horizontal range (one angle: round; 0..90: quadrant; 0..180:
 * bilateral). */
double rad_ies_candela(const rad_ies_profile *profile, double vertical, double horizontal);

typedef enum rad_light_kind {
    RAD_LIGHT_POINT = 0,
    RAD_LIGHT_SPOT,
    RAD_LIGHT_DIRECTIONAL
} rad_light_kind;

typedef struct rad_light {
    char *name;
    rad_light_kind kind;
    rad_vec3 position;  /* point, spot */
    rad_vec3 direction; /* unit: spot axis, or the direction a directional light travels */
    double intensity[3];        /* point, spot: W/sr on the axis; directional: W/m^2 */
    double inner_angle, outer_angle; /* spot: half angles, radians; smooth falloff between */
    rad_ies_profile *ies;       /* owned; NULL: none. With one, I(w) = tint * candela(w) / 179
                                   where tint = intensity / max(intensity) */
} rad_light;

/* The light from `light` reaching x, with its direction and distance: `direction` unit from x
 * towards the light, `distance` INFINITY for directional lights, `irradiance` on a plane at x
 * facing the light (I / r^2 or E_perp). Zero when the light sends nothing towards x. */
typedef struct rad_light_arrival {
    rad_vec3 direction;
    double distance;
    double irradiance[3];
} rad_light_arrival;
int rad_light_arrive(const rad_light *light, rad_vec3 x, rad_light_arrival *out);

/* Radiant intensity (W/sr) of a point or spot light towards unit direction w (from the light). */
void rad_light_intensity(const rad_light *light, rad_vec3 w, double out[3]);

typedef enum rad_sky_kind {
    RAD_SKY_OFF = 0,
    RAD_SKY_UNIFORM,     /* L everywhere above the horizon */
    RAD_SKY_CIE_OVERCAST /* Moon & Spencer 1942 / CIE: L(theta) = L_z (1 + 2 cos theta) / 3 */
} rad_sky_kind;

typedef struct rad_sky {
    rad_sky_kind kind;
    double radiance[3]; /* uniform: L; overcast: L_z at the zenith */
    rad_vec3 up;        /* unit zenith */
    int samples;        /* rays per element of the solver's sky pre-pass */
} rad_sky;

/* Sky radiance seen along unit direction w (towards the sky); zero below the horizon. */
void rad_sky_radiance(const rad_sky *sky, rad_vec3 w, double out[3]);

/* A deep copy of `count` lights (names and profiles), for what outlives the scene; *out NULL
 * when count is 0. */
rad_status rad_lights_copy(rad_context *ctx, const rad_light *lights, size_t count, rad_light **out);

/* Lights owned by a scene: frees names and profiles. */
void rad_lights_free(rad_context *ctx, rad_light *lights, size_t count);

/* Solid angle of triangle (a, b, c) seen from x (Van Oosterom & Strackee 1983); positive when
 * its corners run counter-clockwise seen from x. */
double rad_triangle_solid_angle(rad_vec3 x, rad_vec3 a, rad_vec3 b, rad_vec3 c);

#endif
