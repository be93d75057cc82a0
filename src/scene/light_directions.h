/* light_directions.h - the directions a point or spot light sends its light in, tabulated for
 * sampling: where a light path (a photon) leaves a spot light or an IES profile (docs/lights.md,
 * docs/photonmapping.md "Lights").
 *
 * The sphere of directions about the light's axis is cut into cells, `thetas` equal steps of the
 * angle to the axis from 0 to theta_max (a spot's outer cone, else pi) times `phis` equal steps
 * of the azimuth (one when the light is the same all round: a spot, a round IES profile). Each
 * cell is weighted by its solid angle times the mean of the intensity's shape at its four corners
 * and (twice) its middle, and a direction is drawn as a cell by weight, then uniformly over the
 * cell's solid angle: pdf(w) = P_cell / Omega_cell. A cell whose corners and middle are all dark
 * is never drawn, so no photon leaves where the light sends nothing (pbrt-v4 samples its
 * GoniometricLight from a piecewise-constant image of the profile the same way; Pharr, Jakob &
 * Humphreys 2023, sec. 12.3.3). The estimate stays unbiased wherever the light shines in a drawn
 * cell; a profile whose light lies only between the sample points of one cell (finer than the
 * cells: half a degree along the axis, 2.5 degrees round it) would be missed there.
 *
 * The table holds the shape of the intensity alone (with the light's colour taken out), so lights
 * of one kind, cone and profile share one table. */
#ifndef RAD_SCENE_LIGHT_DIRECTIONS_H
#define RAD_SCENE_LIGHT_DIRECTIONS_H

#include "light/lights.h"

typedef struct rad_light_directions {
    int thetas, phis;
    double theta_max;
    double *cdf;         /* thetas * phis cells, theta-major, normalised: the last is 1 */
    double shape_power;  /* the shape's integral over the sphere (the sum of the cell weights) */
    const rad_light *of; /* the light it was made for (its kind, cone and profile) */
} rad_light_directions;

/* Whether `light` needs a table: a spot light or a light with an IES profile (a bare point light
 * is the same in every direction, and a directional light has one). */
int rad_light_directions_needed(const rad_light *light);

/* Whether the table made for one light serves another: the same kind, cones and profile. */
int rad_light_directions_fit(const rad_light_directions *table, const rad_light *light);

/* The table of `light` (rad_light_directions_needed). */
rad_status rad_light_directions_build(rad_context *ctx, const rad_light *light,
                                      rad_light_directions *out);
void rad_light_directions_free(rad_context *ctx, rad_light_directions *table);

/* The light's shape (its intensity over the largest channel of its colour, summed over the
 * channels and divided by their number) towards unit w. */
double rad_light_shape(const rad_light *light, rad_vec3 w);

/* A direction for two uniform numbers, with the solid-angle density it was drawn with; *pdf 0
 * when the table is empty (the light sends nothing). */
rad_vec3 rad_light_directions_sample(const rad_light_directions *table, const rad_light *light,
                                     double u0, double u1, double *pdf);

#endif
